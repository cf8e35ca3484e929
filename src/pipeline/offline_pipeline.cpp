#include "iraf_vo/pipeline/offline_pipeline.h"

#include "iraf_vo/common/wall_clock.h"

namespace iraf_vo {

OfflinePipeline::OfflinePipeline(FrameSource* source, const EnhanceParams& enhance, const FeatureParams& features,
                                 const PipelineOptions& options)
    : source_(source),
      options_(options),
      front_end_(enhance, features, options.stereo),  // stereo: the images for the sub-pixel refinement
      front_end_right_(enhance, features, true),
      read_queue_(options.queue_capacity),
      front_queue_(options.queue_capacity) {
  reader_ = std::thread([this] { readFrames(); });
  front_ = std::thread([this] { runFrontEnd(); });
}

OfflinePipeline::~OfflinePipeline() { stop(); }

void OfflinePipeline::readFrames() {
  for (long index = options_.first;; ++index) {
    if (stop_) return;
    ReadItem it;
    const auto t0 = SteadyClock::now();
    if (index >= options_.last || !source_->read(index, &it.image)) {
      it.end = true;
      read_queue_.push(std::move(it));
      return;
    }
    const cv::Mat& g = it.image.gray;
    if (it.image.error.empty() && (g.cols != options_.width || g.rows != options_.height)) {
      // Tracking with the wrong intrinsics would give silent garbage: stop with an error naming both files.
      it.fatal = true;
      it.image.error = source_->describe(index) + ": image " + std::to_string(g.cols) + "x" + std::to_string(g.rows) +
                       " does not match the camera " + options_.camera_name + " (" + std::to_string(options_.width) +
                       "x" + std::to_string(options_.height) + ")";
    }
    it.index = index;
    it.ms_read = msSince(t0);
    read_queue_.push(std::move(it));
  }
}

void OfflinePipeline::runFrontEnd() {
  for (;;) {
    ReadItem in;
    if (!read_queue_.pop(&in)) return;  // closed and drained (early stop)
    if (in.end) {
      front_queue_.close();  // next() drains what is queued, then reports the end
      return;
    }
    FrontEndItem it;
    it.index = in.index;
    it.ms_read = in.ms_read;
    it.fatal = in.fatal;
    it.error = !in.image.error.empty();
    it.message = in.image.error;
    if (!it.error) {
      try {
        FrontEndTiming t;
        it.frame = front_end_.process(in.image.gray, in.image.stamp, &t);
        it.ms_enhance = t.ms_enhance;
        it.ms_features = t.ms_features;
        if (options_.stereo && !in.image.right.empty() && in.image.right.size() == in.image.gray.size()) {
          it.right_image = in.image.right;  // its features: rightFeatures(), when the tracker matches the frame
          it.has_right = true;
        } else if (options_.stereo && in.image.load_right) {
          it.load_right = in.image.load_right;  // decoded by rightFeatures(), when the tracker matches the frame
          it.has_right = true;
        }
      } catch (const std::exception& e) {
        it.error = true;
        it.message = e.what();
      }
    }
    it.frame.stamp = in.image.stamp;
    front_queue_.push(std::move(it));
  }
}

bool OfflinePipeline::next(FrontEndItem* item) { return front_queue_.pop(item); }

FeatureFrame OfflinePipeline::rightFeatures(const FrontEndItem& item) {
  right_error_.clear();
  cv::Mat right = item.right_image;
  if (right.empty() && item.load_right && !item.load_right(&right, &right_error_)) return FeatureFrame();
  if (right.size() != cv::Size(item.frame.width, item.frame.height)) {
    right_error_ = "right image " + std::to_string(right.cols) + "x" + std::to_string(right.rows) +
                   " does not match the left one";
    return FeatureFrame();
  }
  FrontEndTiming t;
  FeatureFrame f = front_end_right_.process(right, item.frame.stamp, &t);
  ms_right_ += t.ms_enhance + t.ms_features;
  ++right_processed_;
  return f;
}

void OfflinePipeline::stop() {
  stop_ = true;
  front_queue_.close();
  read_queue_.close();
  if (front_.joinable()) front_.join();
  if (reader_.joinable()) reader_.join();
}

}  // namespace iraf_vo

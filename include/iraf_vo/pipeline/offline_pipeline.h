// The offline pipeline of iraf_vo_run: a reader thread (image decoding) -> a front-end thread (enhance + features)
// -> the caller's thread (tracking), connected by bounded queues so that the stages overlap. ROS-free: images come
// from a FrameSource (frame_source.h: an ASL folder, or a rosbag in iraf_vo_run).
#pragma once

#include <atomic>
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <thread>

#include "iraf_vo/common/bounded_queue.h"
#include "iraf_vo/pipeline/frame_source.h"
#include "iraf_vo/pipeline/front_end.h"

namespace iraf_vo {

struct PipelineOptions {
  long first = 0;  // frames [first, last)
  long last = 0;
  int width = 0, height = 0;  // the camera's image size: another size stops the run (fatal)
  std::string camera_name;    // for that message
  size_t queue_capacity = 4;
  bool stereo = false;  // pass the right images on; rightFeatures() runs a second FrontEnd (same parameters)
};

/// One frame leaving the front-end, in frame order.
struct FrontEndItem {
  long index = 0;
  FeatureFrame frame;
  cv::Mat right_image;     // stereo: the right image (its features: OfflinePipeline::rightFeatures)
  std::function<bool(cv::Mat*, std::string*)> load_right;  // stereo, deferred: decodes right_image (SourceImage)
  bool has_right = false;  // stereo: this frame has a right image
  double ms_read = 0, ms_enhance = 0, ms_features = 0;
  bool error = false;  // unreadable image or front-end failure: skip the frame
  bool fatal = false;  // stop the run (image size != camera size)
  std::string message;
};

class OfflinePipeline {
 public:
  /// Starts the reader and front-end threads. `source` must outlive the pipeline.
  OfflinePipeline(FrameSource* source, const EnhanceParams& enhance, const FeatureParams& features,
                  const PipelineOptions& options);
  ~OfflinePipeline();  // stop()
  OfflinePipeline(const OfflinePipeline&) = delete;
  OfflinePipeline& operator=(const OfflinePipeline&) = delete;

  /// The next frame; false after the last one.
  bool next(FrontEndItem* item);
  /// Stops and joins the threads (early stop: queued frames are dropped).
  void stop();
  /// Stereo: the right image's features (the same enhance + feature parameters as the left), computed on the
  /// caller's thread when the tracker needs them (Tracker::track with RightFeatures); a deferred right image is
  /// decoded here. An unusable right image (unreadable, another size): empty features (no stereo matches for the
  /// frame) and rightError() says why.
  FeatureFrame rightFeatures(const FrontEndItem& item);
  /// Why the last rightFeatures() call had no right image ("" when it had one).
  const std::string& rightError() const { return right_error_; }
  long rightFramesProcessed() const { return right_processed_; }
  double rightFrontEndMs() const { return ms_right_; }  // summed over those frames

 private:
  struct ReadItem {
    long index = 0;
    SourceImage image;
    double ms_read = 0;
    bool end = false, fatal = false;
  };
  void readFrames();
  void runFrontEnd();

  FrameSource* source_;
  PipelineOptions options_;
  FrontEnd front_end_;
  FrontEnd front_end_right_;  // stereo: its own buffers, the same parameters; the caller's thread only
  long right_processed_ = 0;
  double ms_right_ = 0.0;
  std::string right_error_;
  BoundedQueue<ReadItem> read_queue_;
  BoundedQueue<FrontEndItem> front_queue_;
  std::atomic<bool> stop_{false};
  std::thread reader_, front_;
};

}  // namespace iraf_vo

// Where the offline pipeline's images come from: the FrameSource interface, and its implementation for an ASL
// folder. The rosbag implementation is a plugin of the ROS library (bag_frame_source.h). ROS-free.
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <string>

#include "iraf_vo/io/image_folder.h"

namespace iraf_vo {

struct SourceImage {
  double stamp = 0.0;  // seconds
  cv::Mat gray;        // CV_8UC1 (the left image of a stereo pair)
  cv::Mat right;       // CV_8UC1, the right image of a stereo pair; empty when the source has none for this frame
  /// Instead of `right`, from a source that defers it: decodes the right image when called (false + error when it
  /// is unreadable). Set only when the frame has a right partner.
  std::function<bool(cv::Mat* right, std::string* error)> load_right;
  std::string error;   // not empty: the image is unreadable (the frame is skipped)
};

/// A sequence of images read in order.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual size_t size() const = 0;
  /// Reads frame `index`; indices increase by one per call (frames before the first index are skipped).
  /// false when the source ended.
  virtual bool read(long index, SourceImage* out) = 0;
  /// Names frame `index` in messages (its file, or the bag and topic).
  virtual std::string describe(long index) const = 0;
  /// What the user must know before the run ("" if nothing), e.g. a truncated bag read up to its intact part.
  virtual std::string notice() const { return ""; }
  /// "" when no image was skipped so far, else how many and the first reason.
  virtual std::string skippedSummary() const { return ""; }
};

/// The images of an ASL folder (DIR/mav0/cam0); with a right reader (DIR/mav0/cam1) each frame also gets the right
/// image whose timestamp is within kStereoStampTolerance of the left one (none: SourceImage::right stays empty).
/// defer_right: the right PNG is not decoded by read() but by SourceImage::load_right, when the frame uses it (the
/// stereo tracker matches the initialization and keyframes only: a third of the EuRoC frames).
class AslFrameSource : public FrameSource {
 public:
  static constexpr int64_t kStereoStampToleranceNs = 1000000;  // 1 ms: ASL pairs share their stamps
  explicit AslFrameSource(const AslImageReader* reader, const AslImageReader* right = nullptr,
                          bool defer_right = false)
      : reader_(reader), right_(right), defer_right_(defer_right) {}
  size_t size() const override { return reader_->size(); }
  bool read(long index, SourceImage* out) override;
  std::string describe(long index) const override;
  std::string skippedSummary() const override { return reader_->skippedSummary(); }

 private:
  const AslImageReader* reader_;
  const AslImageReader* right_;
  bool defer_right_;
};

}  // namespace iraf_vo

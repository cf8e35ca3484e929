// The offline pipeline of iraf_vo_run: a reader thread (image decoding) -> a front-end thread (enhance + features)
// -> the caller's thread (tracking), connected by bounded queues so that the stages overlap. ROS-free: images come
// from a FrameSource (frame_source.h: an ASL folder, or a rosbag in iraf_vo_run).
#pragma once

#include <atomic>
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
  bool stereo = false;  // run the front-end on the right images too (a second FrontEnd, same parameters)
};

/// One frame leaving the front-end, in frame order.
struct FrontEndItem {
  long index = 0;
  FeatureFrame frame;
  FeatureFrame right;      // stereo: the right image's features
  bool has_right = false;  // stereo: this frame has a right image (right is valid)
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
  FrontEnd front_end_right_;  // stereo: its own buffers, the same parameters
  BoundedQueue<ReadItem> read_queue_;
  BoundedQueue<FrontEndItem> front_queue_;
  std::atomic<bool> stop_{false};
  std::thread reader_, front_;
};

}  // namespace iraf_vo

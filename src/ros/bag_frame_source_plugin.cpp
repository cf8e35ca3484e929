// The rosbag FrameSource behind pipeline/bag_frame_source.h (loaded by the offline runner on first use).
#include "iraf_vo/pipeline/bag_frame_source.h"

#include "iraf_vo/ros/bag_reader.h"

namespace iraf_vo {

namespace {

/// The images of one topic of a rosbag, in bag order.
class BagFrameSource : public FrameSource {
 public:
  BagFrameSource(const std::string& path, const std::string& topic) : name_(path + " (topic " + topic + ")") {}
  bool open(const std::string& path, const std::string& topic, std::string* error) {
    return bag_.open(path, topic, error);
  }
  size_t size() const override { return bag_.size(); }
  bool read(long index, SourceImage* out) override {
    ros::Time t;
    for (; next_ < index; ++next_)
      if (!bag_.next(&t, &out->gray)) return false;
    if (!bag_.next(&t, &out->gray)) return false;
    ++next_;
    out->stamp = t.toSec();
    return true;
  }
  std::string describe(long) const override { return name_; }
  std::string notice() const override { return bag_.notice(); }
  std::string skippedSummary() const override { return bag_.skippedSummary(); }

 private:
  BagImageReader bag_;
  std::string name_;
  long next_ = 0;
};

}  // namespace

}  // namespace iraf_vo

extern "C" __attribute__((visibility("default"))) iraf_vo::FrameSource* iraf_vo_open_bag_frame_source_v1(
    const std::string* path, const std::string* topic, std::string* error) {
  auto source = std::make_unique<iraf_vo::BagFrameSource>(*path, *topic);
  if (!source->open(*path, *topic, error)) return nullptr;
  return source.release();
}

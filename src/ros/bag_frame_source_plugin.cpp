// The rosbag FrameSource behind pipeline/bag_frame_source.h (loaded by the offline runner on first use).
#include <deque>

#include "iraf_vo/pipeline/bag_frame_source.h"
#include "iraf_vo/ros/bag_reader.h"

namespace iraf_vo {

namespace {

/// The images of one topic of a rosbag in bag order; with a right topic, each with its right partner
/// (StereoPairing on the header stamps; both topics are read forward, at most the right images not yet paired are
/// held).
class BagFrameSource : public FrameSource {
 public:
  explicit BagFrameSource(const std::string& path, const BagSourceOptions& o)
      : options_(o), name_(path + " (topic " + o.topic + ")"), pairing_(o.pairing) {}
  bool open(const std::string& path, std::string* error) {
    if (!bag_.open(path, options_.topic, error)) return false;
    return options_.right_topic.empty() || right_bag_.open(path, options_.right_topic, error);
  }
  size_t size() const override { return bag_.size(); }
  bool read(long index, SourceImage* out) override {
    for (SourceImage skipped; next_ < index; ++next_)
      if (!nextLeft(&skipped)) return false;
    if (!nextLeft(out)) return false;
    ++next_;
    return true;
  }
  std::string describe(long) const override { return name_; }
  std::string notice() const override {
    return !bag_.notice().empty() ? bag_.notice() : right_bag_.notice();
  }
  std::string skippedSummary() const override {
    std::string s = bag_.skippedSummary();
    const std::string r = options_.right_topic.empty() ? "" : right_bag_.skippedSummary();
    if (!r.empty()) s += (s.empty() ? "" : "; ") + r;
    const StereoCounters& c = pairing_.counters();
    if (c.left_only > 0 || c.dropped_right > 0)
      s += (s.empty() ? "" : "; ") + std::string("right topic ") + options_.right_topic + ": " +
           std::to_string(c.left_only) + " left image(s) without a right partner (tracked with the left camera), " +
           std::to_string(c.dropped_right) + " right image(s) without a left partner dropped, " +
           std::to_string(c.pairs) + " pairs";
    return s;
  }

 private:
  bool nextLeft(SourceImage* out) {
    ros::Time t;
    out->right.release();
    if (!bag_.next(&t, &out->gray)) return false;
    out->stamp = t.toSec();
    if (options_.right_topic.empty()) return true;
    bool decided = apply(pairing_.addLeft(static_cast<int64_t>(t.toNSec()), t.toSec()), out);
    while (!decided) {
      ros::Time tr;
      cv::Mat right;
      if (right_done_ || !right_bag_.next(&tr, &right)) {
        right_done_ = true;
        decided = apply(pairing_.flush(), out);
        break;
      }
      right_.push_back(right);
      decided = apply(pairing_.addRight(static_cast<int64_t>(tr.toNSec()), tr.toSec()), out);
    }
    return true;
  }

  /// Consumes the decisions; true when one of them was the latest left image's (out->right set for a pair).
  bool apply(const std::vector<StereoPairing::Decision>& decisions, SourceImage* out) {
    bool decided = false;
    for (const StereoPairing::Decision& d : decisions) {
      if (d.kind == StereoPairing::Kind::kPair) out->right = right_.front();
      if (d.kind != StereoPairing::Kind::kLeftOnly) right_.pop_front();
      if (d.kind != StereoPairing::Kind::kDropRight) decided = true;
    }
    return decided;
  }

  BagSourceOptions options_;
  BagImageReader bag_, right_bag_;
  std::string name_;
  long next_ = 0;
  StereoPairing pairing_;
  std::deque<cv::Mat> right_;  // read, not yet paired or dropped (the pairing's right queue)
  bool right_done_ = false;
};

}  // namespace

}  // namespace iraf_vo

extern "C" __attribute__((visibility("default"))) iraf_vo::FrameSource* iraf_vo_open_bag_frame_source_v2(
    const std::string* path, const iraf_vo::BagSourceOptions* options, std::string* error) {
  auto source = std::make_unique<iraf_vo::BagFrameSource>(*path, *options);
  if (!source->open(*path, error)) return nullptr;
  return source.release();
}

#include "iraf_vo/pipeline/frame_source.h"

#include <algorithm>
#include <cstdlib>

namespace iraf_vo {

bool AslFrameSource::read(long index, SourceImage* out) {
  if (index < 0 || index >= static_cast<long>(reader_->size())) return false;
  out->right.release();  // a reused SourceImage keeps no right image of an earlier frame
  out->load_right = nullptr;
  out->error.clear();
  if (!reader_->loadImage(static_cast<size_t>(index), &out->gray, &out->error) && out->error.empty())
    out->error = "unreadable image";
  out->stamp = reader_->entries()[index].stamp();
  if (right_ && out->error.empty()) {
    const int64_t t = reader_->entries()[index].stamp_ns;
    const std::vector<ImageEntry>& r = right_->entries();
    auto it = std::lower_bound(r.begin(), r.end(), t - kStereoStampToleranceNs,
                               [](const ImageEntry& e, int64_t s) { return e.stamp_ns < s; });
    if (it == r.end() || std::llabs(it->stamp_ns - t) > kStereoStampToleranceNs) return true;
    const size_t i = static_cast<size_t>(it - r.begin());
    const AslImageReader* right = right_;
    if (defer_right_) {
      out->load_right = [right, i](cv::Mat* image, std::string* error) { return right->loadImage(i, image, error); };
      return true;
    }
    std::string right_error;  // an unreadable right image: the frame is a left-only frame
    if (!right_->loadImage(i, &out->right, &right_error)) out->right.release();
  }
  return true;
}

std::string AslFrameSource::describe(long index) const { return reader_->entries()[index].path; }

}  // namespace iraf_vo

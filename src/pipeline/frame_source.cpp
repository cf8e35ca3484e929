#include "iraf_vo/pipeline/frame_source.h"

namespace iraf_vo {

bool AslFrameSource::read(long index, SourceImage* out) {
  if (index < 0 || index >= static_cast<long>(reader_->size())) return false;
  if (!reader_->loadImage(static_cast<size_t>(index), &out->gray, &out->error) && out->error.empty())
    out->error = "unreadable image";
  out->stamp = reader_->entries()[index].stamp();
  return true;
}

std::string AslFrameSource::describe(long index) const { return reader_->entries()[index].path; }

}  // namespace iraf_vo

#include "iraf_vo/pipeline/bag_frame_source.h"

#include "iraf_vo/common/shared_library.h"

namespace iraf_vo {

std::unique_ptr<FrameSource> openBagFrameSource(const std::string& path, const BagSourceOptions& options,
                                                std::string* error) {
  static const char* const kLibrary = "libiraf_vo_ros.so";
  std::string why;
  void* h = openSiblingLibrary(kLibrary, &why);
  using Factory = decltype(&iraf_vo_open_bag_frame_source_v2);
  Factory open = h ? reinterpret_cast<Factory>(findLibrarySymbol(h, "iraf_vo_open_bag_frame_source_v2", kLibrary, &why))
                   : nullptr;
  if (!open) {
    if (error) *error = "reading a rosbag needs the ROS part of iraf_vo: " + why;
    return nullptr;
  }
  return std::unique_ptr<FrameSource>(open(&path, &options, error));
}

}  // namespace iraf_vo

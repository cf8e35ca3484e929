// libFuzzer target: bytes -> ASL data.csv parsing (AslImageReader::open) in a temp folder whose data/ holds a
// few image files. open() must succeed with sorted, unique, existing entries or fail with an error naming
// data.csv; never throw or crash. loadImage() of an entry fails cleanly (the files are not valid images).
// Built and run by scripts/fuzz.sh.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "iraf_vo/io/image_folder.h"

#include "fuzz_check.h"

namespace {
// DIR/mav0/cam0/{data.csv, data/{1.png, 2.png, a b.png}} created once per process.
const std::string& camDir() {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    const std::string root = std::string(tmp && *tmp ? tmp : "/tmp") + "/iraf_vo_fuzz_asl_" + std::to_string(getpid());
    const std::string cam = root + "/mav0/cam0";
    for (const std::string& d : {root, root + "/mav0", cam, cam + "/data"}) mkdir(d.c_str(), 0755);
    for (const char* n : {"1.png", "2.png", "a b.png"}) std::ofstream(cam + "/data/" + n) << "not a png";
    return cam;
  }();
  return dir;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string csv = camDir() + "/data.csv";
  {
    std::ofstream f(csv, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  iraf_vo::AslImageReader r;
  std::string err;
  if (!r.open(camDir(), &err)) {
    FUZZ_CHECK(err.find("data.csv") != std::string::npos);
    return 0;
  }
  FUZZ_CHECK(!r.empty());
  for (size_t i = 1; i < r.size(); ++i) FUZZ_CHECK(r.entries()[i - 1].stamp_ns < r.entries()[i].stamp_ns);
  cv::Mat gray;
  std::string img_err;
  FUZZ_CHECK(!r.loadImage(0, &gray, &img_err));  // not a real image: must fail cleanly, naming the file
  FUZZ_CHECK(img_err.find(r.entries()[0].path) != std::string::npos);
  return 0;
}

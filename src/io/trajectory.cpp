#include "iraf_vo/io/trajectory.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <sstream>

#include "iraf_vo/common/file_util.h"

namespace iraf_vo {

namespace {

/// Splits on commas (csv) or whitespace.
std::vector<std::string> split(const std::string& line, bool csv) {
  std::vector<std::string> out;
  if (csv) {
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) out.push_back(trim(f));
  } else {
    std::stringstream ss(line);
    std::string f;
    while (ss >> f) out.push_back(f);
  }
  return out;
}

bool toDouble(const std::string& s, double* v) {
  if (s.empty()) return false;
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0';
}

/// Timestamp in seconds from a field holding seconds or (if > 1e12) nanoseconds. Integer nanoseconds are
/// parsed as int64 so no precision is lost before the conversion.
bool toStamp(const std::string& s, double* t, bool force_ns) {
  const bool integer = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  if (integer && s.size() <= 19) {
    long long v = 0;  // from_chars: a 19-digit value above INT64_MAX is malformed (std::stoll threw)
    const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
    if (res.ec != std::errc() || res.ptr != s.data() + s.size()) return false;
    if (force_ns || v > 1000000000000LL) {
      *t = static_cast<double>(v / 1000000000LL) + static_cast<double>(v % 1000000000LL) * 1e-9;
      return true;
    }
    *t = static_cast<double>(v);
    return true;
  }
  if (!toDouble(s, t) || !std::isfinite(*t)) return false;
  if (force_ns || *t > 1e12) *t *= 1e-9;
  return true;
}

void warn(std::vector<std::string>* w, const std::string& m) {
  if (w) w->push_back(m);
}

/// Shared reader: TUM (whitespace, t x y z qx qy qz qw) or EuRoC (csv, t_ns x y z qw qx qy qz ...).
bool readPoses(const std::string& path, bool euroc, const Eigen::Matrix4d& T_BS, Trajectory* traj, std::string* error,
               std::vector<std::string>* warnings) {
  traj->clear();
  std::ifstream in(path);
  if (!in) {
    if (error) *error = path + ": cannot open trajectory file";
    return false;
  }
  Eigen::Isometry3d T_bs = Eigen::Isometry3d::Identity();
  T_bs.matrix() = T_BS;
  std::string line;
  int line_no = 0, n_bad = 0;
  std::string first_bad;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == '%') continue;
    const std::vector<std::string> f = split(t, euroc);
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    auto bad = [&](const std::string& why) {
      const std::string m = where + why + " in '" + (t.size() > 80 ? t.substr(0, 80) + "..." : t) + "', skipped";
      warn(warnings, m);
      if (n_bad++ == 0) first_bad = m;
    };
    if (euroc ? f.size() < 8 : f.size() != 8) {
      bad("expected " + std::string(euroc ? "at least 8 comma-separated" : "8 whitespace-separated") + " fields, got " +
          std::to_string(f.size()));
      continue;
    }
    double stamp = 0.0;
    if (!toStamp(f[0], &stamp, euroc)) {
      bad("bad timestamp '" + f[0] + "'");
      continue;
    }
    double v[7];
    bool ok = true;
    for (int k = 0; k < 7 && ok; ++k) ok = toDouble(f[k + 1], &v[k]) && std::isfinite(v[k]);
    if (!ok) {
      bad("non-numeric or non-finite value");
      continue;
    }
    // TUM: qx qy qz qw; EuRoC: qw qx qy qz.
    Eigen::Quaterniond q = euroc ? Eigen::Quaterniond(v[3], v[4], v[5], v[6]) : Eigen::Quaterniond(v[6], v[3], v[4], v[5]);
    const double qn = q.norm();
    if (!(qn > 1e-6) || std::abs(qn - 1.0) > 1e-2) {
      bad("quaternion norm " + std::to_string(qn) + " is not ~1");
      continue;
    }
    q.normalize();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    if (euroc) T = T * T_bs;  // T_W_C = T_W_B * T_BS
    traj->push_back(stamp, T);
  }
  const size_t dropped = traj->sortAndUnique();
  if (dropped) warn(warnings, path + ": " + std::to_string(dropped) + " duplicated timestamps dropped");
  if (traj->empty()) {
    if (error) *error = path + ": no valid pose" + (first_bad.empty() ? " (empty file?)" : " (first problem: " + first_bad + ")");
    return false;
  }
  return true;
}

}  // namespace

size_t Trajectory::sortAndUnique() {
  std::vector<size_t> idx(stamps.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return stamps[a] < stamps[b]; });
  Trajectory out;
  for (size_t i : idx) {
    if (!out.empty() && stamps[i] == out.stamps.back()) continue;
    out.push_back(stamps[i], poses[i]);
  }
  const size_t dropped = stamps.size() - out.size();
  *this = std::move(out);
  return dropped;
}

bool readTumTrajectory(const std::string& path, Trajectory* traj, std::string* error, std::vector<std::string>* warnings) {
  return readPoses(path, false, Eigen::Matrix4d::Identity(), traj, error, warnings);
}

bool readEurocGroundTruth(const std::string& path, Trajectory* traj, std::string* error, const Eigen::Matrix4d& T_BS,
                          std::vector<std::string>* warnings) {
  if (!T_BS.allFinite()) {
    if (error) *error = path + ": T_BS is not finite";
    return false;
  }
  return readPoses(path, true, T_BS, traj, error, warnings);
}

bool readTrajectory(const std::string& path_in, Trajectory* traj, std::string* error, const Eigen::Matrix4d& T_BS,
                    std::vector<std::string>* warnings) {
  std::string path = path_in;
  if (isDir(path)) {
    for (const char* rel : {"/mav0/state_groundtruth_estimate0/data.csv", "/state_groundtruth_estimate0/data.csv",
                            "/mav0/mocap0/data.csv", "/mocap0/data.csv"}) {
      if (isFile(path + rel)) {
        path += rel;
        break;
      }
    }
    if (isDir(path)) {
      if (error) *error = path + ": directory holds no [mav0/]state_groundtruth_estimate0/data.csv or [mav0/]mocap0/data.csv";
      return false;
    }
  }
  std::ifstream in(path);
  if (!in) {
    if (error) *error = path + ": cannot open trajectory file";
    return false;
  }
  std::string line;
  while (std::getline(in, line)) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == '%') continue;
    const bool csv = t.find(',') != std::string::npos;
    return csv ? readEurocGroundTruth(path, traj, error, T_BS, warnings) : readTumTrajectory(path, traj, error, warnings);
  }
  if (error) *error = path + ": no data line (empty trajectory file)";
  return false;
}

bool writeTumTrajectory(const std::string& path, const Trajectory& traj, std::string* error) {
  if (traj.stamps.size() != traj.poses.size()) {
    if (error) *error = path + ": trajectory has " + std::to_string(traj.stamps.size()) + " stamps but " +
                        std::to_string(traj.poses.size()) + " poses";
    return false;
  }
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    if (error) *error = path + ": cannot open for writing";
    return false;
  }
  std::fprintf(f, "# timestamp[s] tx ty tz qx qy qz qw\n");
  for (size_t i = 0; i < traj.size(); ++i) {
    const Eigen::Vector3d p = traj.poses[i].translation();
    Eigen::Quaterniond q(traj.poses[i].rotation());
    q.normalize();
    if (q.w() < 0) q.coeffs() *= -1.0;  // canonical sign
    std::fprintf(f, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", traj.stamps[i], p.x(), p.y(), p.z(), q.x(), q.y(),
                 q.z(), q.w());
  }
  const bool ok = std::fclose(f) == 0;
  if (!ok && error) *error = path + ": write failed";
  return ok;
}

}  // namespace iraf_vo

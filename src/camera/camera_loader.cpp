#include "iraf_vo/camera/camera_loader.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/LU>
#include <cmath>
#include <fstream>
#include <sstream>

#include "iraf_vo/camera/kannala_brandt.h"
#include "iraf_vo/camera/pinhole_radtan.h"
#include "iraf_vo/common/error_out.h"

namespace iraf_vo {

namespace {

std::string num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

/// Thrown internally with "key 'x': what" messages; caught at the top and prefixed with the file.
struct KeyError {
  std::string msg;
};

[[noreturn]] void fail(const std::string& key, const std::string& what) { throw KeyError{"key '" + key + "': " + what}; }

YAML::Node require(const YAML::Node& parent, const std::string& key) {
  const YAML::Node n = parent[key];
  if (!n) fail(key, "missing");
  return n;
}

double toDouble(const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) fail(key, "expected a number");
  const std::string s = n.Scalar();
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    // yaml-cpp only knows .nan/.inf; accept "nan"/"inf" spellings too so they are reported as such below.
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    if (s.empty() || end == s.c_str() || *end != '\0') fail(key, "not a number ('" + s + "')");
  }
  return v;
}

int toInt(const YAML::Node& n, const std::string& key) {
  const double v = toDouble(n, key);
  if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > 1e9) fail(key, "not an integer ('" + n.Scalar() + "')");
  return static_cast<int>(v);
}

std::vector<double> toVector(const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence()) fail(key, "expected a list of numbers");
  std::vector<double> v;
  for (size_t i = 0; i < n.size(); ++i) v.push_back(toDouble(n[i], key + "[" + std::to_string(i) + "]"));
  return v;
}

/// {rows, cols, data} matrix (ROS camera_info / EuRoC T_BS / OpenCV FileStorage style).
std::vector<double> toMatrix(const YAML::Node& n, const std::string& key, int rows, int cols) {
  if (!n.IsMap()) fail(key, "expected a map {rows, cols, data}");
  const int r = toInt(require(n, "rows"), key + ".rows");
  const int c = toInt(require(n, "cols"), key + ".cols");
  if (rows > 0 && r != rows) fail(key + ".rows", "expected " + std::to_string(rows) + ", got " + std::to_string(r));
  if (cols > 0 && c != cols) fail(key + ".cols", "expected " + std::to_string(cols) + ", got " + std::to_string(c));
  std::vector<double> d = toVector(require(n, "data"), key + ".data");
  const long long rc = static_cast<long long>(r) * c;  // 64-bit: rows, cols up to 1e9 each
  if (static_cast<long long>(d.size()) != rc)
    fail(key + ".data", "expected rows*cols = " + std::to_string(rc) + " values, got " + std::to_string(d.size()));
  return d;
}

Eigen::Matrix4d toPose(const std::vector<double>& d, const std::string& key) {
  Eigen::Matrix4d T;
  for (int i = 0; i < 16; ++i) {
    if (!std::isfinite(d[i])) fail(key, "value " + std::to_string(i) + " is not finite");
    T(i / 4, i % 4) = d[i];
  }
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-6) fail(key, "last row must be [0, 0, 0, 1]");
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-3 || R.determinant() < 0.0)
    fail(key, "rotation part is not a rotation matrix");
  return T;
}

void checkResolution(int w, int h, const std::string& key) {
  if (w <= 0 || h <= 0) fail(key, "resolution must be positive (got " + std::to_string(w) + "x" + std::to_string(h) + ")");
}

/// EuRoC sensor.yaml / Kalibr camchain entry.
CameraModelPtr parseKalibr(const YAML::Node& root, const std::string& prefix, std::string* msg) {
  const std::string cm_key = prefix + "camera_model";
  const std::string camera_model = require(root, "camera_model").as<std::string>("");
  if (camera_model != "pinhole")
    fail(cm_key, "unknown camera model '" + camera_model + "' (supported: pinhole)");
  const std::vector<double> intr = toVector(require(root, "intrinsics"), prefix + "intrinsics");
  if (intr.size() != 4) fail(prefix + "intrinsics", "expected 4 values [fu, fv, cu, cv], got " + std::to_string(intr.size()));
  const std::vector<double> res = toVector(require(root, "resolution"), prefix + "resolution");
  if (res.size() != 2) fail(prefix + "resolution", "expected 2 values [width, height], got " + std::to_string(res.size()));
  for (double r : res)
    if (!std::isfinite(r) || r != std::floor(r) || std::abs(r) > 1e9)  // int cast below (fuzz_camera_yaml: 5.7e19)
      fail(prefix + "resolution", "width/height must be integers (|value| <= 1e9)");
  checkResolution(static_cast<int>(res[0]), static_cast<int>(res[1]), prefix + "resolution");

  std::string dm = root["distortion_model"] ? root["distortion_model"].as<std::string>("") : "none";
  std::string coeff_key = root["distortion_coeffs"] && !root["distortion_coefficients"] ? "distortion_coeffs" : "distortion_coefficients";
  std::vector<double> dist;
  if (dm != "none") dist = toVector(require(root, coeff_key), prefix + coeff_key);
  std::string model;
  if (dm == "radial-tangential" || dm == "radtan" || dm == "plumb_bob") {
    model = "pinhole-radtan";
    if (dist.size() != 4 && dist.size() != 5)
      fail(prefix + coeff_key, "radial-tangential needs 4 values [k1, k2, p1, p2] (or 5 with k3), got " + std::to_string(dist.size()));
  } else if (dm == "equidistant" || dm == "equi" || dm == "fisheye") {
    model = "kannala-brandt";
    if (dist.size() != 4) fail(prefix + coeff_key, "equidistant needs 4 values [k1, k2, k3, k4], got " + std::to_string(dist.size()));
  } else if (dm == "none") {
    model = "pinhole-radtan";
    dist.assign(4, 0.0);
  } else {
    fail(prefix + "distortion_model", "unknown distortion model '" + dm + "' (supported: radial-tangential, equidistant, none)");
  }

  Eigen::Matrix4d T_BS = Eigen::Matrix4d::Identity();
  if (root["T_BS"]) {
    T_BS = toPose(toMatrix(root["T_BS"], prefix + "T_BS", 4, 4), prefix + "T_BS");
  } else if (root["T_cam_imu"]) {
    const YAML::Node t = root["T_cam_imu"];
    std::vector<double> d;
    if (t.IsSequence() && t.size() == 4) {
      for (size_t i = 0; i < 4; ++i) {
        std::vector<double> row = toVector(t[i], prefix + "T_cam_imu[" + std::to_string(i) + "]");
        if (row.size() != 4) fail(prefix + "T_cam_imu", "expected 4 rows of 4 values");
        d.insert(d.end(), row.begin(), row.end());
      }
    } else {
      fail(prefix + "T_cam_imu", "expected 4 rows of 4 values");
    }
    T_BS = toPose(d, prefix + "T_cam_imu").inverse();
  }

  std::vector<double> params = intr;
  params.insert(params.end(), dist.begin(), dist.end());
  std::string err;
  CameraModelPtr cam = makeCamera(model, static_cast<int>(res[0]), static_cast<int>(res[1]), params, &err, T_BS);
  if (!cam) fail(err.rfind("fx", 0) == 0 || err.rfind("fy", 0) == 0 || err.rfind("cx", 0) == 0 || err.rfind("cy", 0) == 0
                     ? prefix + "intrinsics" : prefix + coeff_key, err);
  return cam;
}

/// ROS camera_info yaml.
CameraModelPtr parseCameraInfo(const YAML::Node& root) {
  const int w = toInt(require(root, "image_width"), "image_width");
  const int h = toInt(require(root, "image_height"), "image_height");
  if (w <= 0) fail("image_width", "must be positive (got " + std::to_string(w) + ")");
  if (h <= 0) fail("image_height", "must be positive (got " + std::to_string(h) + ")");
  const std::vector<double> K = toMatrix(require(root, "camera_matrix"), "camera_matrix", 3, 3);
  const std::string dm = require(root, "distortion_model").as<std::string>("");
  std::vector<double> D;
  const YAML::Node dn = require(root, "distortion_coefficients");
  D = dn.IsMap() ? toMatrix(dn, "distortion_coefficients", 0, 0) : toVector(dn, "distortion_coefficients");
  std::string model;
  if (dm == "plumb_bob" || dm == "radial-tangential" || dm == "radtan") {
    model = "pinhole-radtan";
    if (D.size() != 4 && D.size() != 5)
      fail("distortion_coefficients", "plumb_bob needs 4 or 5 values [k1, k2, p1, p2, k3], got " + std::to_string(D.size()));
  } else if (dm == "equidistant" || dm == "fisheye") {
    model = "kannala-brandt";
    if (D.size() != 4) fail("distortion_coefficients", "equidistant needs 4 values [k1, k2, k3, k4], got " + std::to_string(D.size()));
  } else {
    fail("distortion_model", "unknown distortion model '" + dm + "' (supported: plumb_bob, equidistant)");
  }
  if (K[1] != 0.0 || K[3] != 0.0 || K[6] != 0.0 || K[7] != 0.0 || K[8] != 1.0)
    fail("camera_matrix", "expected [fx 0 cx; 0 fy cy; 0 0 1] (no skew)");
  std::vector<double> params{K[0], K[4], K[2], K[5]};
  params.insert(params.end(), D.begin(), D.end());
  std::string err;
  CameraModelPtr cam = makeCamera(model, w, h, params, &err);
  if (!cam) fail(err.rfind("k", 0) == 0 || err.rfind("p", 0) == 0 ? "distortion_coefficients" : "camera_matrix", err);
  return cam;
}

}  // namespace

CameraModelPtr makeCamera(const std::string& model, int width, int height, const std::vector<double>& p,
                          std::string* error, const Eigen::Matrix4d& T_BS) {
  if (width <= 0 || height <= 0) {
    setError(error, "resolution must be positive (got " + std::to_string(width) + "x" + std::to_string(height) + ")");
    return nullptr;
  }
  const char* names_radtan[] = {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"};
  const char* names_kb[] = {"fx", "fy", "cx", "cy", "k1", "k2", "k3", "k4"};
  const bool radtan = model == "pinhole-radtan";
  if (!radtan && model != "kannala-brandt") {
    setError(error, "unknown camera model '" + model + "' (supported: pinhole-radtan, kannala-brandt)");
    return nullptr;
  }
  if (radtan ? (p.size() != 8 && p.size() != 9) : p.size() != 8) {
    setError(error, "model " + model + " needs " + (radtan ? "8 (or 9)" : "8") + " parameters, got " + std::to_string(p.size()));
    return nullptr;
  }
  for (size_t i = 0; i < p.size(); ++i) {
    const char* name = radtan ? names_radtan[i] : names_kb[i];
    if (!std::isfinite(p[i])) {
      setError(error, std::string(name) + " = " + num(p[i]) + " is not finite");
      return nullptr;
    }
    if (i < 2 && !(p[i] > 0.0)) {
      setError(error, std::string(name) + " = " + num(p[i]) + " must be > 0");
      return nullptr;
    }
    // Magnitude bounds (far beyond any real camera): fy = 4.6e298 loaded fine and project() then returned
    // "success" with inf pixels (found by fuzz_camera_yaml).
    const double limit = i < 4 ? 1e7 : 1e6;
    if (std::abs(p[i]) > limit) {
      setError(error, std::string(name) + " = " + num(p[i]) + " is out of range (|value| <= " + num(limit) + ")");
      return nullptr;
    }
  }
  if (!T_BS.allFinite()) {
    setError(error, "T_BS is not finite");
    return nullptr;
  }
  std::shared_ptr<CameraModel> cam;
  if (radtan) {
    cam = std::make_shared<PinholeRadtan>(width, height, p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7],
                                          p.size() == 9 ? p[8] : 0.0);
  } else {
    cam = std::make_shared<KannalaBrandt>(width, height, p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]);
  }
  cam->T_BS = T_BS;
  return cam;
}

CameraModelPtr loadCameraFromString(const std::string& yaml_text, const std::string& source, std::string* error) {
  // Strip an OpenCV-style "%YAML:1.0" directive (yaml-cpp rejects the colon form).
  std::string text = yaml_text;
  {
    size_t pos = 0;
    while (pos < text.size() && (text[pos] == ' ' || text[pos] == '\t' || text[pos] == '\n' || text[pos] == '\r')) ++pos;
    if (text.compare(pos, 5, "%YAML") == 0) {
      const size_t eol = text.find('\n', pos);
      text = eol == std::string::npos ? std::string() : text.substr(eol + 1);
    }
  }
  try {
    YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) {
      setError(error, source + ": not a yaml map (empty or wrong file?)");
      return nullptr;
    }
    if (root["camera_matrix"]) return parseCameraInfo(root);
    if (root["intrinsics"] || root["camera_model"]) return parseKalibr(root, "", error);
    if (root["cam0"] && root["cam0"].IsMap()) return parseKalibr(root["cam0"], "cam0.", error);
    setError(error, source + ": key 'intrinsics' (EuRoC/Kalibr) or 'camera_matrix' (ROS camera_info): missing");
    return nullptr;
  } catch (const KeyError& e) {
    setError(error, source + ": " + e.msg);
  } catch (const YAML::Exception& e) {
    setError(error, source + ": yaml parse error: " + e.what());
  }
  return nullptr;
}

CameraModelPtr loadCamera(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    setError(error, path + ": cannot open camera file");
    return nullptr;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  return loadCameraFromString(ss.str(), path, error);
}

bool saveCamera(const CameraModel& camera, const std::string& path, std::string* error) {
  const std::vector<double> p = camera.parameters();
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "sensor_type" << YAML::Value << "camera";
  out << YAML::Key << "comment" << YAML::Value << ("written by iraf_vo (" + camera.modelName() + ")");
  out << YAML::Key << "T_BS" << YAML::Value << YAML::BeginMap << YAML::Key << "cols" << YAML::Value << 4
      << YAML::Key << "rows" << YAML::Value << 4 << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int i = 0; i < 16; ++i) out << camera.T_BS(i / 4, i % 4);
  out << YAML::EndSeq << YAML::EndMap;
  out << YAML::Key << "resolution" << YAML::Value << YAML::Flow << YAML::BeginSeq << camera.width() << camera.height()
      << YAML::EndSeq;
  out << YAML::Key << "camera_model" << YAML::Value << "pinhole";
  out << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << YAML::BeginSeq << p[0] << p[1] << p[2] << p[3]
      << YAML::EndSeq;
  out << YAML::Key << "distortion_model" << YAML::Value << camera.distortionModel();
  out << YAML::Key << "distortion_coefficients" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (size_t i = 4; i < p.size(); ++i) out << p[i];
  out << YAML::EndSeq << YAML::EndMap;
  std::ofstream f(path);
  if (!f) {
    setError(error, path + ": cannot write camera file");
    return false;
  }
  f << out.c_str() << "\n";
  if (!f) {
    setError(error, path + ": write failed");
    return false;
  }
  return true;
}

}  // namespace iraf_vo

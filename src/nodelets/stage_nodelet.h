// The skeleton shared by the stage nodelets (image_proc style): a dynamic_reconfigure server on the private
// namespace whose Config is copied into the stage's parameter struct through its ParamTable (validated field by
// field: a rejected value is logged with its reason and reverted in the server; accepted changes are logged; stored
// under a mutex, copied per frame), and lazy subscription: inputs are subscribed only while an output has listeners.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>

#include <boost/thread/recursive_mutex.hpp>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "iraf_vo/pipeline/run_monitor.h"
#include "param_bridge.h"

namespace iraf_vo {

/// A ROS-free HealthReport into a /diagnostics status.
inline void fillDiagnostics(const HealthReport& r, diagnostic_updater::DiagnosticStatusWrapper& d) {
  d.summary(static_cast<unsigned char>(r.level), r.summary);
  for (const auto& kv : r.values) d.add(kv.first, kv.second);
}

/// A diagnostic_updater named after the nodelet: status "<nodelet name without the leading />: <task>", e.g.
/// "tracker: tracking"; hardware id "iraf_vo". Updated by the caller (force_update from a wall timer: no sim time).
inline std::shared_ptr<diagnostic_updater::Updater> makeUpdater(ros::NodeHandle& nh,
                                                                ros::NodeHandle& pnh, const std::string& name) {
  auto u = std::make_shared<diagnostic_updater::Updater>(nh, pnh, name);  // it drops name[0] = '/'
  u->setHardwareID("iraf_vo");
  return u;
}

template <class Params, class Config>
class StageNodelet : public nodelet::Nodelet {
 public:
  explicit StageNodelet(const ParamTable<Params>& table) : table_(table) {}

 protected:
  // ---- reconfigurable parameters ----
  /// Starts the server; its first callback brings the startup values (private parameters / cfg defaults).
  /// Before, it records which table fields the user gave as private parameters (userSet(): "section.name"). The
  /// server writes every field back to the parameter server, where a later run on the same roscore finds them:
  /// ~reconfigure_written lists the fields this nodelet wrote without the user giving them (with their values), and
  /// such a leftover (same value) is not user-given.
  void startReconfigure() {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::map<std::string, std::string> written;
    pnh.getParam(kWrittenParam, written);
    for (const ParamEntry<Params>& e : table_.entries()) {
      std::string value;
      if (!paramText(pnh, e.name, &value)) continue;
      const auto it = written.find(e.name);
      if (it != written.end() && it->second == value) continue;  // our own write-back of an earlier run
      user_set_.insert(table_.section() + "." + e.name);
    }
    reconfigure_ = std::make_shared<dynamic_reconfigure::Server<Config>>(reconfigure_mutex_, pnh);
    reconfigure_->setCallback([this](Config& c, uint32_t) { configure(c); });
  }
  /// A copy of the current parameters (per frame).
  Params params() const {
    std::lock_guard<std::mutex> lock(params_mutex_);
    return params_;
  }
  /// Parameters in use until the first accepted Config (before startReconfigure()).
  void setParams(const Params& p) {
    std::lock_guard<std::mutex> lock(params_mutex_);
    params_ = p;
  }
  /// The startup values before startReconfigure(): every table field from the private parameters (e.g. a YAML
  /// section); a bad value is skipped with an error naming the key, an invalid combination falls back to `defaults`.
  void readStartupParams(const Params& defaults, const std::function<std::string(const Params&)>& validate) {
    Params p = defaults;
    std::vector<std::string> errors;
    readPrivateParams(table_, getPrivateNodeHandle(), &p, &errors);
    for (const std::string& e : errors) NODELET_ERROR("%s: %s", section(), e.c_str());
    const std::string err = validate(p);
    if (!err.empty()) NODELET_ERROR("%s: %s; using the defaults", section(), err.c_str());
    setParams(err.empty() ? p : defaults);
  }
  /// Fields given as private parameters at startup ("section.name"): the resolution rule keeps them.
  const std::set<std::string>& userSet() const { return user_set_; }
  /// Replaces the parameters from the node itself (e.g. the resolution rule) and shows them in dynamic_reconfigure.
  void replaceParams(const Params& p) {
    setParams(p);
    boost::recursive_mutex::scoped_lock lock(reconfigure_mutex_);
    if (!reconfigure_ || !have_config_) return;
    paramsToConfig(table_, p, &config_);
    reconfigure_->updateConfig(config_);
    recordWritten(p);
  }
  /// Called after each accepted change with the new parameters and the Config (for nodelet-only fields).
  virtual void onParams(const Params& p, const Config& c) {}
  /// Appended to each logged change when it does not apply at once (e.g. ": stored, applies at the next reset").
  virtual std::string changeNote() { return ""; }
  const ParamTable<Params>& table() const { return table_; }

  // ---- lazy subscription ----
  virtual bool hasListeners() = 0;
  virtual void subscribeInputs() = 0;
  virtual void unsubscribeInputs() = 0;
  /// Held while advertising in onInit, so that connectCb() sees every publisher.
  std::mutex& connectMutex() { return connect_mutex_; }
  /// (Un)subscribes the inputs when the number of listeners changed between zero and non-zero.
  void connectCb() {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    if (!hasListeners()) {
      if (subscribed_) unsubscribeInputs();
      subscribed_ = false;
    } else if (!subscribed_) {
      subscribeInputs();
      subscribed_ = true;
    }
  }
  template <class Msg>
  ros::Publisher advertiseLazy(ros::NodeHandle& nh, const std::string& topic, uint32_t queue) {
    auto cb = [this](const ros::SingleSubscriberPublisher&) { connectCb(); };
    return nh.advertise<Msg>(topic, queue, cb, cb);
  }
  image_transport::Publisher advertiseLazy(image_transport::ImageTransport& it, const std::string& topic,
                                           uint32_t queue) {
    auto cb = [this](const image_transport::SingleSubscriberPublisher&) { connectCb(); };
    return it.advertise(topic, queue, cb, cb);
  }

 private:
  // One dynamic_reconfigure request. Each changed field is applied on its own terms: a value the table cannot take
  // (unknown enum name) or that makes the parameters invalid is rejected with its reason and the value in use is
  // written back into `c` (the server then shows what is in use: a rejected field never blocks later changes);
  // every accepted change is logged ("enhance: mu_expected 112 -> 60"), deferred ones with the subclass's note.
  void configure(Config& c) {
    const Params cur = params();
    Params requested = cur;
    std::vector<std::string> errors;
    configToParams(table_, c, &requested, &errors);  // a field it cannot take keeps its value (and says why)
    for (const std::string& e : errors) NODELET_ERROR("%s: rejected: %s; keeping the value in use", section(), e.c_str());
    Params p = requested;
    if (!table_.validate(p).empty()) {  // some change makes the set invalid: apply the changed fields one by one
      p = cur;
      for (const ParamEntry<Params>& e : table_.entries()) {
        const std::string want = table_.get(requested, e);
        if (want == table_.get(cur, e)) continue;
        Params trial = p;
        copyField(e, requested, &trial);
        std::string err = table_.validate(trial);
        while (!err.empty() && (err.back() == ' ' || err.back() == ';')) err.pop_back();
        if (err.empty()) p = trial;
        else NODELET_ERROR("%s: rejected %s = %s: %s; keeping %s", section(), e.name.c_str(), want.c_str(),
                           err.c_str(), table_.get(cur, e).c_str());
      }
      if (!table_.validate(p).empty()) p = cur;  // (each alone valid, but not together)
    }
    if (have_config_) {
      const std::string note = changeNote();
      for (const ParamEntry<Params>& e : table_.entries()) {
        const std::string before = table_.get(cur, e), after = table_.get(p, e);
        if (before != after)
          NODELET_INFO("%s: %s %s -> %s%s", section(), e.name.c_str(), before.c_str(), after.c_str(), note.c_str());
      }
    }
    paramsToConfig(table_, p, &c);  // what is in use, back to the server (rqt / dynparam show it)
    recordWritten(p);
    setParams(p);
    config_ = c;  // under reconfigure_mutex_ (the server holds it during callbacks)
    have_config_ = true;
    onParams(p, c);
  }
  static constexpr const char* kWrittenParam = "reconfigure_written";
  /// The private parameter `name` as the text ParamTable::get() gives for that value; false when it is not set.
  static bool paramText(const ros::NodeHandle& pnh, const std::string& name, std::string* text) {
    XmlRpc::XmlRpcValue v;
    if (!pnh.getParam(name, v)) return false;
    switch (v.getType()) {
      case XmlRpc::XmlRpcValue::TypeBoolean: *text = static_cast<bool>(v) ? "true" : "false"; return true;
      case XmlRpc::XmlRpcValue::TypeInt: *text = std::to_string(static_cast<int>(v)); return true;
      case XmlRpc::XmlRpcValue::TypeDouble: *text = formatDouble(static_cast<double>(v)); return true;
      case XmlRpc::XmlRpcValue::TypeString: *text = static_cast<std::string>(v); return true;
      default: *text = ""; return true;  // present but not a scalar: the user's (readPrivateParams reports it)
    }
  }
  /// ~reconfigure_written: the fields the server writes back that the user did not give, with their values.
  void recordWritten(const Params& p) {
    std::map<std::string, std::string> written;
    for (const ParamEntry<Params>& e : table_.entries())
      if (!user_set_.count(table_.section() + "." + e.name)) written[e.name] = table_.get(p, e);
    getPrivateNodeHandle().setParam(kWrittenParam, written);
  }
  static void copyField(const ParamEntry<Params>& e, const Params& from, Params* to) {
    switch (e.type) {
      case ParamType::kInt: to->*(e.int_field) = from.*(e.int_field); break;
      case ParamType::kDouble: to->*(e.double_field) = from.*(e.double_field); break;
      case ParamType::kBool: to->*(e.bool_field) = from.*(e.bool_field); break;
      case ParamType::kText: e.set_text(e.get_text(from), to); break;
    }
  }
  const char* section() const { return table_.section().c_str(); }

  const ParamTable<Params>& table_;
  boost::recursive_mutex reconfigure_mutex_;
  std::shared_ptr<dynamic_reconfigure::Server<Config>> reconfigure_;
  Config config_;  // the last accepted Config (reconfigure_mutex_)
  bool have_config_ = false;
  std::set<std::string> user_set_;
  mutable std::mutex params_mutex_;
  Params params_;
  std::mutex connect_mutex_;
  bool subscribed_ = false;
};

}  // namespace iraf_vo

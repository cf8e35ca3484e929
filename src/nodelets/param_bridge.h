// A stage's ParamTable <-> ROS: the generated dynamic_reconfigure Config (typed, through the Config's own parameter
// descriptions: no per-field code, no text round trip) and the nodelet's private parameters.
#pragma once

#include <ros/node_handle.h>

#include <boost/pointer_cast.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "iraf_vo/common/param_table.h"

namespace iraf_vo {

/// The member of Config that the description `d` stands for, or null when its type is not T.
template <class T, class Config>
T Config::*configField(const typename Config::AbstractParamDescriptionConstPtr& d) {
  const auto typed = boost::dynamic_pointer_cast<const typename Config::template ParamDescription<T>>(d);
  return typed ? typed->field : nullptr;
}

/// Copies every Config parameter the table lists into *p (same names, checked by test_params); parameters without a
/// table entry (nodelet-only, e.g. enhance `enabled`) are skipped. Fields marked odd are rounded up to odd. A value
/// the table rejects (an unknown enum name) or a type mismatch keeps the field and adds a message to *errors.
template <class S, class Config>
void configToParams(const ParamTable<S>& table, const Config& c, S* p, std::vector<std::string>* errors) {
  for (const auto& d : Config::__getParamDescriptions__()) {
    const ParamEntry<S>* e = table.find(d->name);
    if (!e) continue;
    bool ok = false;
    std::string err = "cannot use " + table.section() + " parameter '" + e->name + "' (cfg type " + d->type + ")";
    if (e->type == ParamType::kInt) {
      if (const auto f = configField<int, Config>(d)) p->*(e->int_field) = e->odd ? (c.*f | 1) : c.*f, ok = true;
    } else if (e->type == ParamType::kDouble) {
      if (const auto f = configField<double, Config>(d)) p->*(e->double_field) = c.*f, ok = true;
    } else if (e->type == ParamType::kBool) {
      if (const auto f = configField<bool, Config>(d)) p->*(e->bool_field) = c.*f, ok = true;
    } else if (const auto f = configField<std::string, Config>(d)) {
      ok = table.set(p, e->name, c.*f, &err);  // an enum by name
    }
    if (!ok) errors->push_back(err);
  }
}

/// The reverse of configToParams: every table field the Config has is written into *c (for updateConfig).
template <class S, class Config>
void paramsToConfig(const ParamTable<S>& table, const S& p, Config* c) {
  for (const auto& d : Config::__getParamDescriptions__()) {
    const ParamEntry<S>* e = table.find(d->name);
    if (!e) continue;
    if (e->type == ParamType::kInt) {
      if (const auto f = configField<int, Config>(d)) c->*f = p.*(e->int_field);
    } else if (e->type == ParamType::kDouble) {
      if (const auto f = configField<double, Config>(d)) c->*f = p.*(e->double_field);
    } else if (e->type == ParamType::kBool) {
      if (const auto f = configField<bool, Config>(d)) c->*f = p.*(e->bool_field);
    } else if (const auto f = configField<std::string, Config>(d)) {
      c->*f = table.get(p, *e);
    }
  }
}

/// Reads each table entry present as a private parameter (~name) into *p; a value of the wrong type is skipped with
/// a message naming the key in *errors.
template <class S>
void readPrivateParams(const ParamTable<S>& table, const ros::NodeHandle& pnh, S* p, std::vector<std::string>* errors) {
  for (const ParamEntry<S>& e : table.entries()) {
    XmlRpc::XmlRpcValue v;
    if (!pnh.getParam(e.name, v)) continue;
    std::ostringstream s;
    switch (v.getType()) {
      case XmlRpc::XmlRpcValue::TypeBoolean: s << (static_cast<bool>(v) ? "true" : "false"); break;
      case XmlRpc::XmlRpcValue::TypeInt: s << static_cast<int>(v); break;
      case XmlRpc::XmlRpcValue::TypeDouble: s << formatDouble(static_cast<double>(v)); break;
      case XmlRpc::XmlRpcValue::TypeString: s << static_cast<std::string>(v); break;
      default: errors->push_back("ignoring ~" + e.name + ": not a scalar"); continue;
    }
    std::string err;
    if (!table.set(p, e.name, s.str(), &err)) errors->push_back("ignoring ~" + e.name + ": " + err);
  }
}

}  // namespace iraf_vo

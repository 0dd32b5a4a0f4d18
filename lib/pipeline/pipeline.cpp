#include "cdbench/pipeline/pipeline.h"

#include "cdbench/core/error.h"

namespace cdb {

const char* box_precision_name(BoxPrecision p) {
  return p == BoxPrecision::q16 ? "q16" : p == BoxPrecision::fp64 ? "fp64" : "fp32";
}

BoxPrecision parse_box_precision(const std::string& name) {
  if (name == "fp32") return BoxPrecision::fp32;
  if (name == "fp64") return BoxPrecision::fp64;
  if (name == "q16") return BoxPrecision::q16;
  fail("unknown box precision '" + name + "' (known: fp32, fp64, q16)");
}

const char* auto_switch_name(AutoSwitch w) {
  return w == AutoSwitch::on ? "on" : w == AutoSwitch::off ? "off" : "auto";
}

AutoSwitch parse_auto_switch(const std::string& name) {
  if (name == "auto") return AutoSwitch::automatic;
  if (name == "on") return AutoSwitch::on;
  if (name == "off") return AutoSwitch::off;
  fail("unknown choice '" + name + "' (known: auto, on, off)");
}

}  // namespace cdb

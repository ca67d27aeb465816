// The model loader on arbitrary bytes, JSON and MJCF alike (a first byte of '<' reads as MJCF,
// as a .xml file would). Every input either loads or raises ModelError with one bounded line of
// printable ASCII (at most 600 bytes from a short file name); a loaded model has every derived
// quantity finite and positive where it must be. Anything else (another exception, a crash, a
// sanitizer report, a hang) is a bug.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "puppet/model/mjcf.h"
#include "puppet/model/model.h"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

void check_model(const puppet::Model& model) {
  check(model.segment_count() >= 1 && model.joint_count() == model.segment_count() - 1);
  check(std::isfinite(model.total_mass) && model.total_mass > 0.0);
  check(std::isfinite(model.rest_height) && model.rest_height > 0.0);
  for (const puppet::Segment& s : model.segments) {
    check(std::isfinite(s.inv_mass) && s.inv_mass > 0.0);
    check(s.inv_inertia.allFinite() && (s.inv_inertia.array() > 0.0).all());
    check(s.rest_position.allFinite());
    check(std::abs(s.rest_orientation.norm() - 1.0) < 1e-9);
    check(!s.shapes.empty());
    for (const puppet::Shape& shape : s.shapes) {
      check(shape.position.allFinite());
      check(std::abs(shape.orientation.norm() - 1.0) < 1e-9);
    }
  }
  for (const puppet::Joint& j : model.joints) {
    check(j.anchor_in_parent.allFinite() && j.anchor_in_child.allFinite());
    check(std::abs(j.frame_in_parent.norm() - 1.0) < 1e-9);
    check(std::abs(j.hinge_axis.norm() - 1.0) < 1e-9);
    // a range holds the rest; only a slide's may be infinite (not limited)
    check(j.lower <= 0.0 && j.upper >= 0.0);
    check(j.type == puppet::JointType::kSlide ||
          (std::isfinite(j.lower) && std::isfinite(j.upper)));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const bool xml = !text.empty() && text[0] == '<';
    check_model(xml ? puppet::parse_mjcf(text, "fuzz.xml")
                    : puppet::parse_model(text, "fuzz.json"));
  } catch (const puppet::ModelError& error) {
    const std::string message = error.what();
    check(message.size() <= 600);  // the testbed prints at most 400 of it
    for (const char c : message) check(c >= 0x20 && c < 0x7f);
  }
  return 0;
}

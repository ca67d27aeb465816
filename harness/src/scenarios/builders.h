// What the scenarios share (scenarios/*.cpp, one file each): the figure held by its head, its
// hand or both, at rest or from a random start; the figure free; the row a file gives the
// catalogue (catalogue.cpp).
#pragma once

#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "puppet/compare/scenario.h"
#include "puppet/model/root_joint.h"

namespace puppet::compare {

// one scenario of the catalogue (catalogue.cpp lists them): its name, as --scenario, the CSVs
// and the plots spell it, and how to build it; make_scenario sets the name and applies the
// command line's overrides of the environment afterwards. One row is the headline: the
// scenario a table quotes when it quotes one (headline_scenario()).
struct ScenarioRow {
  std::string_view name;
  std::string_view asks;  // what the scenario asks of a solver, and why (testbed list, REPORT.md)
  Scenario (*make)(const Model& model, const ScenarioOptions& options) = nullptr;
  bool headline = false;
  // a scene on the ground, judged by its violations, its first impact and its outcomes over
  // random starts rather than by its trajectory (contact_judge.h)
  bool contact = false;
};

// a held hand: the segment named (else the one reaching lowest at rest), its point from --grab
// or its lowest at rest (a random start picks its own), and the path its target follows
struct HandPath {
  std::string_view segment;  // the default segment's name in the Pinocchio model
  TargetPath path = TargetPath::kCircle;
  double radius = 0.0;  // m
  double hz = 0.0;
  // the user's grab (ScenarioOptions::grab_spring's law), else a hard pin on the path (the
  // seed's marionette string), compliant by --grab-compliance
  bool grab = false;
};

// the circle of drag, marionette, water, tremble and yank (docs/design.md): 0.3 m, at --hz or a
// start's; held by the grab when `grab`, else by a hard pin
HandPath circling_hand(const ScenarioOptions& options, bool grab);

// The figure at rest (or at options.start, posed from the segment held first), with gravity the
// model's and no other force. `head`: a marionette, its head's top (--pin) fixed where it is, the
// figure tilted by --tilt (or the start's) about world x through it. `hand`: a second pin on a
// hand whose target follows the path: the grab, or a pin compliant by --grab-compliance.
// The turns a held root's figure can make without leaving its hold: the whole figure about the
// root's hinge through its anchor (a ball's: about any axis, `axis` empty); for a welded or a
// sliding root, each child of the root with its subtree about its joint (a hinge's axis, a ball's
// any)
struct HeldTurn {
  int top = 0;  // the subtree's top segment
  Vector3d centre{0, 0, 0};
  std::optional<Vector3d> axis;
};
std::vector<HeldTurn> held_turns(const Model& model);
// turns (or sets spinning at ω about `centre`) the segments of the subtree under `top`
void turn_subtree(const Model& model, int top, const Quaterniond& rotation, const Vector3d& centre,
                  std::vector<BodyState>& bodies);
void spin_subtree(const Model& model, int top, const Vector3d& omega, const Vector3d& centre,
                  std::vector<BodyState>& bodies);

Scenario held_figure(const Model& model, const ScenarioOptions& options, bool head,
                     const std::optional<HandPath>& hand);

// The free figure (at rest, or at options.start posed from its root) for a scene on the ground:
// tilted by `tilt_deg` about world x through its centre of mass, its lowest point `height` above
// the ground (friction 0.8), in air drag 0.05/s, for 3 s.
Scenario figure_on_ground(const Model& model, const ScenarioOptions& options, double tilt_deg,
                          double height);

// the centre of mass of a state
Vector3d centre_of_mass(const Model& model, const std::vector<BodyState>& bodies);
// every body rotated rigidly by `rotation` about `centre`
void rotate_about(std::span<BodyState> bodies, const Quaterniond& rotation, const Vector3d& centre);

}  // namespace puppet::compare

// The crowd's lane path: batches of xpbd puppets stepped together, one per SIMD lane, by the
// kernel of the widest instruction set the processor has (lane_kernel.h). A puppet's state stays
// in its Solver; a batch is copied into lanes, stepped, and copied back. Private to the crowd.
#pragma once

#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "lane_kernel.h"
#include "puppet/procedural/solver.h"

namespace puppet::procedural::lanes {

class LaneStepper {
 public:
  // a stepper for puppets made like `puppet` (every puppet of a crowd is), or null when they
  // cannot be stepped in lanes: a rule other than xpbd, water, the ground, either tremble, timed
  // stages, a model too large to keep its anchor orders, or `max_width` under 2. Its width is the
  // widest the processor has up to `max_width` (8: AVX-512, 4: AVX2, 2: SSE2)
  static std::unique_ptr<LaneStepper> make(const Solver& puppet, int max_width);
  ~LaneStepper();

  int width() const { return width_; }

  // one thread's copy of a batch in lanes, sized once
  class Scratch {
   public:
    explicit Scratch(const LaneStepper& stepper);
    double* slots() { return slots_.get(); }

   private:
    struct Free {
      void operator()(double* p) const;
    };
    std::unique_ptr<double[], Free> slots_;
  };

  // steps `puppets` by dt, as Solver::step would each: in batches of up to width() puppets
  // with the same pins (count and segments), a batch short of puppets with its last lanes idle.
  // A lane that meets a non-finite value is stepped again alone from its start, so that its
  // divergence is flagged exactly as a lone solver flags it. Allocates nothing.
  void step(std::span<Solver* const> puppets, double dt, Scratch& scratch) const;

 private:
  LaneStepper(const Solver& puppet, int width);
  // one batch of puppets with the same pins, in lanes
  void step_batch(std::span<Solver* const> batch, double dt, Scratch& scratch) const;

  int width_ = 1;
  unsigned (*kernel_)(const Plan&, double*) = nullptr;
  int segments_ = 0, joints_ = 0;
  std::vector<SegmentTerms> segment_terms_;
  std::vector<JointPlan> joint_plans_;
  std::vector<std::vector<int>> orders_;  // by anchor: the joints in AnchorOrder::links' order
  std::pair<const Model*, const ModelTables*> limit_context_;  // lane_limit_error's
  Plan base_;                                                  // all but h, the order and the pins
};

}  // namespace puppet::procedural::lanes

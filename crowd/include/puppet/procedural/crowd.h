/// \file
/// Many independent puppets of one model, stepped together on a fixed set of threads: the
/// batched path for crowds. Each puppet is a Solver and keeps the single-puppet API.
///
/// Rule xpbd's puppets are stepped in SIMD lanes (CrowdLanes): a batch of 8 puppets (AVX-512), 4
/// (AVX2) or 2 (SSE2) runs one substep kernel together, one puppet per lane. A lane does a lone
/// solver's arithmetic but for the order of a few products, so it matches a lone Solver to rounding
/// (the tests bound the difference), and it gives the same bits on either instruction set and in
/// any batch. Every other puppet, and every puppet of the kNone path, reaches bit for bit the state
/// a lone Solver reaches from the same inputs. Either way the result does not depend on the
/// number of threads (each puppet is stepped by exactly one thread, in the same arithmetic).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "puppet/procedural/solver.h"

namespace puppet::procedural {

namespace lanes {
class LaneStepper;
}

/// how a crowd of xpbd puppets uses SIMD lanes: the widest the processor has (AVX-512's 8
/// puppets, else AVX2's 4, else SSE2's 2), at most AVX2's 4, SSE2's 2 on any processor, or none
/// (one Solver::step per puppet). Puppets of other rules, in water, on the ground or trembling
/// are always stepped one by one, and so is a puppet while a grab (Pin::is_grab) holds it.
enum class CrowdLanes { kWidest, kFour, kTwo, kNone };

class Crowd {
 public:
  /// `threads` ≥ 1 counts the calling thread: threads − 1 workers are started here and wait
  /// between steps. Throws std::invalid_argument on invalid settings or counts.
  Crowd(const Model& model, const Settings& settings, const Environment& environment, int puppets,
        int threads, CrowdLanes lanes = CrowdLanes::kWidest);
  ~Crowd();
  Crowd(const Crowd&) = delete;
  Crowd& operator=(const Crowd&) = delete;

  int size() const { return static_cast<int>(puppets_.size()); }
  int threads() const { return static_cast<int>(workers_.size()) + 1; }
  /// puppets stepped together: 8, 4, 2, or 1 when the puppets are stepped one by one
  int lanes() const;
  Solver& puppet(int k) { return *puppets_[k]; }
  const Solver& puppet(int k) const { return *puppets_[k]; }

  /// what the user does to puppet k just before it steps (move its pins' targets, set its
  /// forces), called on the thread that steps it: the puppet is in that core's cache then, and
  /// the work is shared between the threads instead of being a serial pass over every puppet.
  /// In lanes, it is called for each puppet of a chunk (16 puppets) before the chunk steps.
  using Control = std::function<void(int k, Solver& puppet)>;

  /// steps every puppet by dt (each with its own pins and targets), calling `control` (when not
  /// empty) for each just before; returns when all are done. Puppets are split into one
  /// contiguous range per thread; a thread done with its own takes chunks from the back of the
  /// others'. Nothing is allocated (build `control` once, outside the loop).
  void step(double dt, const Control& control = {});

 private:
  void step_range(int thread, double dt, const Control& control);
  /// puppets [begin, end) in lanes, on `thread`
  void step_lanes(int thread, int begin, int end, double dt, const Control& control);
  /// the next chunk of `owner`'s range, from its front for the owner, else from its back
  bool take(int owner, bool own, int* begin, int* end);
  void work(int thread);

  std::vector<std::unique_ptr<Solver>> puppets_;
  std::unique_ptr<lanes::LaneStepper> lanes_;  ///< null when the puppets step one by one
  struct LaneScratch;
  std::vector<std::unique_ptr<LaneScratch>> lane_scratch_;  ///< one per thread
  std::vector<Solver*> puppet_pointers_;                    ///< puppets_, for batches
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  long generation_ = 0;  ///< one per step, guarded by mutex_
  int pending_ = 0;      ///< workers still stepping the current generation
  double dt_ = 0.0;
  const Control* control_ = nullptr;  ///< the current step's, guarded like dt_
  bool stop_ = false;
  /// each thread's range of puppets this step, (front, back) in one word; written before the
  /// workers are woken (under mutex_), then moved only by compare-and-swap
  struct alignas(64) Range {
    std::atomic<uint64_t> span{0};
  };
  std::unique_ptr<Range[]> ranges_;
};

}  // namespace puppet::procedural

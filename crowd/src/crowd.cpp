#include "puppet/procedural/crowd.h"

#include <algorithm>
#include <span>
#include <stdexcept>

#include "lanes/lane_stepper.h"

namespace puppet::procedural {

struct Crowd::LaneScratch : lanes::LaneStepper::Scratch {
  using Scratch::Scratch;
};

Crowd::Crowd(const Model& model, const Settings& settings, const Environment& environment,
             int puppets, int threads, CrowdLanes lanes) {
  if (puppets < 1) throw std::invalid_argument("a crowd needs at least one puppet");
  if (threads < 1) throw std::invalid_argument("a crowd needs at least one thread");
  puppets_.reserve(puppets);
  const std::shared_ptr<const ModelTables> tables = make_model_tables(model);
  for (int k = 0; k < puppets; ++k) {
    puppets_.push_back(std::make_unique<Solver>(model, settings, environment, tables));
    puppet_pointers_.push_back(puppets_.back().get());
  }
  const int max_width = lanes == CrowdLanes::kWidest ? 8
                        : lanes == CrowdLanes::kFour ? 4
                        : lanes == CrowdLanes::kTwo  ? 2
                                                     : 0;
  lanes_ = lanes::LaneStepper::make(*puppets_[0], max_width);
  if (lanes_) {
    for (int t = 0; t < threads; ++t)
      lane_scratch_.push_back(std::make_unique<LaneScratch>(*lanes_));
  }
  ranges_ = std::make_unique<Range[]>(threads);
  for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { work(t); });
}

int Crowd::lanes() const { return lanes_ ? lanes_->width() : 1; }

Crowd::~Crowd() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

namespace {

constexpr int kChunk = 16;  // puppets taken at a time: ~20 µs of work, a negligible CAS

// (front, back) of a range of puppets packed in one word, so that both ends move atomically
uint64_t pack(uint32_t front, uint32_t back) { return static_cast<uint64_t>(front) << 32 | back; }
uint32_t front_of(uint64_t span) { return static_cast<uint32_t>(span >> 32); }
uint32_t back_of(uint64_t span) { return static_cast<uint32_t>(span); }

// where thread t's own range of n puppets starts (and thread t − 1's ends)
uint32_t range_start(long n, long t, long parts) { return static_cast<uint32_t>(n * t / parts); }

}  // namespace

bool Crowd::take(int owner, bool own, int* begin, int* end) {
  std::atomic<uint64_t>& span = ranges_[owner].span;
  uint64_t seen = span.load(std::memory_order_relaxed);
  for (;;) {
    const uint32_t front = front_of(seen), back = back_of(seen);
    if (front >= back) return false;
    // the owner takes from the front, in order; another thread from the back
    const uint32_t cut = own ? std::min(back, front + kChunk)
                             : std::max(front, back - std::min<uint32_t>(back, kChunk));
    const uint64_t next = own ? pack(cut, back) : pack(front, cut);
    if (span.compare_exchange_weak(seen, next, std::memory_order_relaxed)) {
      *begin = static_cast<int>(own ? front : cut);
      *end = static_cast<int>(own ? cut : back);
      return true;
    }
  }
}

void Crowd::step_range(int thread, double dt, const Control& control) {
  // its own contiguous range first (the same puppets every step: they stay in this core's
  // cache), then what is left at the back of the others' (a late worker does not hold the step)
  const long n = size(), parts = threads();
  const int own_end = static_cast<int>(range_start(n, thread + 1, parts));
  for (int i = 0; i < parts; ++i) {
    const int owner = static_cast<int>((thread + i) % parts);
    const bool own = owner == thread;
    int begin = 0, end = 0;
    while (take(owner, own, &begin, &end)) {
      if (lanes_) {
        step_lanes(thread, begin, end, dt, control);
        continue;
      }
      // prefetch across its own chunks, which follow each other
      const int prefetch_end = own ? own_end : end;
      for (int k = begin; k < end; ++k) {
        if (k + 2 < prefetch_end) puppets_[k + 2]->prefetch();
        if (control) control(k, *puppets_[k]);
        puppets_[k]->step(dt);
      }
    }
  }
}

void Crowd::step_lanes(int thread, int begin, int end, double dt, const Control& control) {
  if (control) {
    for (int k = begin; k < end; ++k) control(k, *puppets_[k]);
  }
  lanes_->step(std::span(puppet_pointers_).subspan(begin, end - begin), dt, *lane_scratch_[thread]);
}

void Crowd::work(int thread) {
  long seen = 0;
  for (;;) {
    double dt = 0.0;
    const Control* control = nullptr;
    {
      std::unique_lock lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      dt = dt_;
      control = control_;
    }
    step_range(thread, dt, *control);
    {
      std::lock_guard lock(mutex_);
      --pending_;
    }
    done_.notify_one();
  }
}

void Crowd::step(double dt, const Control& control) {
  const long n = size(), parts = threads();
  for (int t = 0; t < parts; ++t) {
    ranges_[t].span.store(pack(range_start(n, t, parts), range_start(n, t + 1, parts)),
                          std::memory_order_relaxed);
  }
  if (!workers_.empty()) {
    {
      std::lock_guard lock(mutex_);
      dt_ = dt;
      control_ = &control;
      pending_ = static_cast<int>(workers_.size());
      ++generation_;
    }
    start_.notify_all();
  }
  step_range(0, dt, control);
  if (!workers_.empty()) {
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return pending_ == 0; });
  }
}

}  // namespace puppet::procedural

#include "puppet/procedural/crowd.h"

#include <stdexcept>

namespace puppet::procedural {

Crowd::Crowd(const Model& model, const Settings& settings, const Environment& environment,
             int puppets, int threads) {
  if (puppets < 1) throw std::invalid_argument("a crowd needs at least one puppet");
  if (threads < 1) throw std::invalid_argument("a crowd needs at least one thread");
  puppets_.reserve(puppets);
  const std::shared_ptr<const ModelTables> tables = make_model_tables(model);
  for (int k = 0; k < puppets; ++k) {
    puppets_.push_back(std::make_unique<Solver>(model, settings, environment, tables));
  }
  for (int t = 1; t < threads; ++t) workers_.emplace_back([this, t] { work(t); });
}

Crowd::~Crowd() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void Crowd::step_range(int thread, double dt, const Control& control) {
  const int n = size(), parts = threads();
  const int begin = static_cast<int>(static_cast<long>(n) * thread / parts);
  const int end = static_cast<int>(static_cast<long>(n) * (thread + 1) / parts);
  for (int k = begin; k < end; ++k) {
    if (k + 2 < end) puppets_[k + 2]->prefetch();
    if (control) control(k, *puppets_[k]);
    puppets_[k]->step(dt);
  }
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

// Rods hanging from the origin and the analytic physical pendulum: shared by the tests of every
// solver, so that each is checked against the same independent answer.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "puppet/model/environment.h"
#include "puppet/model/model.h"

namespace puppet::test {

// one or two 0.8 m rods (1 kg capsules) hanging from the origin, tied by a free ball joint
inline Model rods(int count) {
  std::string json = R"({"name":"rods","segments":[)";
  for (int i = 0; i < count; ++i) {
    json += std::string(i ? "," : "") + R"({"name":"rod)" + std::to_string(i) +
            R"(","mass":1,"position":[0,0,)" + std::to_string(-0.4 - 0.8 * i) +
            R"(],"shape":{"type":"capsule","radius":0.02,"half_length":0.38}})";
  }
  json += "]";
  if (count == 2) {
    json +=
        R"(,"joints":[{"name":"j","parent":"rod0","child":"rod1","anchor":[0,0,-0.8],"type":"ball","swing_deg":[180,180],"twist_deg":180}])";
  }
  return parse_model(json + "}", "rods");
}

// rods at angles θ about world x from hanging straight down, at rest
inline std::vector<BodyState> rods_at(const std::vector<double>& angles) {
  std::vector<BodyState> bodies(angles.size());
  Vector3d top{0, 0, 0};
  for (size_t i = 0; i < angles.size(); ++i) {
    const Quaterniond q(Eigen::AngleAxisd(angles[i], Vector3d::UnitX()));
    bodies[i].q = q;
    bodies[i].x = top + q * Vector3d(0, 0, -0.4);
    top += q * Vector3d(0, 0, -0.8);
  }
  return bodies;
}

// the top of the first rod, held at the origin
inline Pin top_pin() {
  Pin pin;
  pin.segment = 0;
  pin.local_point = Vector3d(0, 0, 0.4);
  return pin;
}

// the period of one rod swinging about its top at `amplitude` (rad), g = 9.81
inline double analytic_period(double amplitude) {
  const Model model = rods(1);
  const double pivot_inertia = model.segments[0].inertia.x() + 1.0 * 0.4 * 0.4;
  const double small = 2 * M_PI * std::sqrt(pivot_inertia / (9.81 * 0.4));
  // finite-amplitude series of the complete elliptic integral
  return small * (1 + amplitude * amplitude / 16 + 11 * std::pow(amplitude, 4) / 3072);
}

// Collects upward zero crossings of an angular velocity, interpolated within the step, and
// gives the mean period between them.
class PeriodMeter {
 public:
  void add(double t, double dt, double w) {
    if (previous_ < 0.0 && w >= 0.0) crossings_.push_back(t - dt * w / (w - previous_));
    previous_ = w;
  }
  double period() const {
    if (crossings_.size() < 3) return NAN;
    return (crossings_.back() - crossings_.front()) / static_cast<double>(crossings_.size() - 1);
  }

 private:
  std::vector<double> crossings_;
  double previous_ = 0.0;
};

// Collects every zero crossing of a damped swing's coordinate (both ways), interpolated within
// the step, and the largest magnitude of each half swing before it: a damped oscillator's half
// period is the crossings' mean spacing, its decay per half swing the peaks' ratio.
class SwingMeter {
 public:
  explicit SwingMeter(double start) : previous_(start) {}
  void add(double t, double dt, double value) {
    peak_ = std::max(peak_, std::abs(value));
    if ((previous_ > 0.0) != (value > 0.0)) {
      crossings_.push_back(t - dt * value / (value - previous_));
      peaks_.push_back(peak_);
      peak_ = 0.0;
    }
    previous_ = value;
  }
  const std::vector<double>& crossings() const { return crossings_; }
  const std::vector<double>& peaks() const { return peaks_; }

 private:
  std::vector<double> crossings_, peaks_;
  double previous_, peak_ = 0.0;
};

// the double physical pendulum of two identical rods, planar, by Lagrange; RK4 at 1e-4 s
struct DoublePendulum {
  double m = 1, length = 0.8, inertia, g = 9.81;
  explicit DoublePendulum(double com_inertia) : inertia(com_inertia) {}
  // [θ1, θ2, θ1', θ2'] → derivative
  Eigen::Vector4d derivative(const Eigen::Vector4d& s) const {
    const double c = m * length * length / 2, delta = s[0] - s[1];
    Eigen::Matrix2d mass;
    mass << m * length * length * 1.25 + inertia, c * std::cos(delta), c * std::cos(delta),
        m * length * length / 4 + inertia;
    const Eigen::Vector2d rhs(
        -c * std::sin(delta) * s[3] * s[3] - 1.5 * m * g * length * std::sin(s[0]),
        c * std::sin(delta) * s[2] * s[2] - 0.5 * m * g * length * std::sin(s[1]));
    const Eigen::Vector2d acc = mass.inverse() * rhs;
    return {s[2], s[3], acc[0], acc[1]};
  }
  void advance(Eigen::Vector4d& s, double h) const {
    const Eigen::Vector4d k1 = derivative(s), k2 = derivative(s + h / 2 * k1),
                          k3 = derivative(s + h / 2 * k2), k4 = derivative(s + h * k3);
    s += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
};

}  // namespace puppet::test

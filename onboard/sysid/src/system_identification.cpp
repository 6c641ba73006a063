#include "uav/sysid/system_identification.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "uav/shared/text_file.hpp"

namespace uav::sysid {
namespace {

constexpr int kSubsteps = 20;  // per log row, for the continuous-time models

// Servo channels as the log's chirp column numbers them (control::ServoChannel).
enum Channel { kAileron = 1, kElevator = 2, kThrottle = 3, kRudder = 4 };
// Wirings as the log's att_mode column numbers them (hal::AttitudeMode).
enum Mode { kDirect = 0, kGyroHover = 1, kGyroCruise = 2 };

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',') out.push_back(cur), cur.clear();
    else if (c != '\r') cur.push_back(c);
  }
  out.push_back(cur);
  return out;
}

// Unit-gain chain of `order` equal first-order lags (time constant tau) driven by the input u_k,
// held from row k to row k+1 and seen `delay` seconds late. Returns, per row, the state at the
// row's time (interval_mean false) or its mean over the interval that ends there.
std::vector<double> SimulateLag(const std::vector<double>& u, double dt, double tau, int order, double delay,
                                bool interval_mean) {
  const double h = dt / kSubsteps;
  const double a = std::exp(-h / tau);
  std::vector<double> out(u.size(), u.empty() ? 0.0 : u[0]);
  double x1 = u.empty() ? 0.0 : u[0], x2 = x1;  // start in steady state
  const long delay_steps = std::lround(delay / h);
  for (std::size_t k = 1; k < u.size(); ++k) {
    double sum = 0.0;
    for (int s = 0; s < kSubsteps; ++s) {
      const long j = static_cast<long>(k - 1) * kSubsteps + s - delay_steps;
      const double in = u[static_cast<std::size_t>(std::max(0L, j / kSubsteps))];
      const double before = order == 2 ? x2 : x1;
      x1 = a * x1 + (1 - a) * in;
      if (order == 2) x2 = a * x2 + (1 - a) * x1;
      sum += 0.5 * (before + (order == 2 ? x2 : x1));  // trapezoid: the mean to O(h^2)
    }
    out[k] = interval_mean ? sum / kSubsteps : (order == 2 ? x2 : x1);
  }
  return out;
}

// Least squares y ~ gain * x + offset; returns the sum of squared residuals.
double FitGainOffset(const std::vector<double>& x, const std::vector<double>& y, double* gain, double* offset) {
  Eigen::MatrixXd A(x.size(), 2);
  Eigen::VectorXd b(y.size());
  for (std::size_t i = 0; i < x.size(); ++i) A(i, 0) = x[i], A(i, 1) = 1.0, b(i) = y[i];
  const Eigen::Vector2d sol = A.colPivHouseholderQr().solve(b);
  *gain = sol(0);
  *offset = sol(1);
  return (A * sol - b).squaredNorm();
}

// Golden-section search for the minimum of f over [lo, hi].
double GoldenMin(const std::function<double(double)>& f, double lo, double hi, int iterations = 60) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double a = lo, b = hi, c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(c), fd = f(d);
  for (int i = 0; i < iterations; ++i) {
    if (fc < fd) b = d, d = c, fd = fc, c = b - g * (b - a), fc = f(c);
    else a = c, c = d, fc = fd, d = a + g * (b - a), fd = f(d);
  }
  return (a + b) / 2;
}

double FitPercent(const std::vector<double>& y, const std::vector<double>& yhat) {
  double mean = 0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(y.size());
  double num = 0, den = 0;
  for (std::size_t i = 0; i < y.size(); ++i) num += std::pow(y[i] - yhat[i], 2), den += std::pow(y[i] - mean, 2);
  return den > 0 ? 100.0 * (1.0 - std::sqrt(num / den)) : 0.0;
}

struct LagModel {
  double gain = 0, tau = 0, delay = 0, offset = 0;
  std::vector<double> predicted;
};

// Output-error fit of y = gain * lag^order(u, tau, delay) + offset: tau by golden section (on a
// log scale), delay on a 10 ms grid when `max_delay` > 0, gain and offset by least squares.
LagModel FitLag(const std::vector<double>& u, const std::vector<double>& y, double dt, int order,
                bool interval_mean, double max_delay) {
  LagModel best;
  double best_sse = 1e300;
  for (double delay = 0.0; delay <= max_delay + 1e-9; delay += 0.01) {
    auto sse = [&](double log_tau) {
      double g, o;
      return FitGainOffset(SimulateLag(u, dt, std::exp(log_tau), order, delay, interval_mean), y, &g, &o);
    };
    const double log_tau = GoldenMin(sse, std::log(0.005), std::log(3.0));
    const double e = sse(log_tau);
    if (e < best_sse) {
      best_sse = e;
      best.tau = std::exp(log_tau);
      best.delay = delay;
    }
  }
  const auto x = SimulateLag(u, dt, best.tau, order, best.delay, interval_mean);
  FitGainOffset(x, y, &best.gain, &best.offset);
  best.predicted.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) best.predicted[i] = best.gain * x[i] + best.offset;
  return best;
}

std::vector<double> Slice(const std::vector<double>& v, std::size_t i0, std::size_t i1) {
  return {v.begin() + static_cast<long>(i0), v.begin() + static_cast<long>(i1)};
}

}  // namespace

LogTable LogTable::ReadCsv(const std::string& path) { return Parse(ReadTextFile(path, "flight log"), path); }

LogTable LogTable::Parse(const std::string& text, const std::string& source) {
  LogTable t;
  t.source_ = source;
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line.empty()) throw std::runtime_error(source + ": empty, no header row");
  const auto names = SplitCsv(line);
  std::vector<std::vector<double>*> cols;
  for (const auto& n : names) cols.push_back(&t.columns_[n]);
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    const auto fields = SplitCsv(line);
    if (fields.size() != names.size()) {
      // A log cut by a crash ends in a partial row: that one is dropped, any other is an error.
      if (in.peek() == std::char_traits<char>::eof()) break;
      throw std::runtime_error(source + ":" + std::to_string(line_no) + ": " + std::to_string(fields.size()) +
                               " fields, the header has " + std::to_string(names.size()));
    }
    for (std::size_t i = 0; i < fields.size(); ++i) {
      char* end = nullptr;
      const double v = std::strtod(fields[i].c_str(), &end);
      if (fields[i] == "nan") {
        t.first_nan_line_.emplace(names[i], line_no);
        cols[i]->push_back(v);
        continue;
      }
      if (fields[i].empty() || *end != '\0' || !std::isfinite(v))
        throw std::runtime_error(source + ":" + std::to_string(line_no) + ": column " + names[i] + " is '" +
                                 fields[i] + "', not a finite number");
      cols[i]->push_back(v);
    }
    ++t.rows_;
  }
  if (t.rows_ < 2) throw std::runtime_error(source + ": fewer than two rows of data");
  return t;
}

const std::vector<double>& LogTable::Column(const std::string& name) const {
  auto it = columns_.find(name);
  if (it == columns_.end()) throw std::runtime_error(source_ + ": no column '" + name + "'");
  auto nan = first_nan_line_.find(name);
  if (nan != first_nan_line_.end())
    throw std::runtime_error(source_ + ":" + std::to_string(nan->second) + ": column " + name +
                             " is 'nan', not a finite number");
  return it->second;
}

KnownParams KnownParams::FromParameters(const ParameterSet& p) {
  return {p.Get("mass"), p.Get("gravity"), p.Get("rotor_speed_gain"),
          {p.Get("inertia_xx"), p.Get("inertia_yy"), p.Get("inertia_zz")}};
}

Identification Identify(const LogTable& log, const KnownParams& known) {
  Identification id;
  const auto& t = log.Column("t");
  const auto& chirp = log.Column("chirp");
  const auto& mode = log.Column("att_mode");
  const auto& task = log.Column("task");
  const auto& armed = log.Column("armed");
  const std::size_t n = log.rows();
  const double dt = (t[n - 1] - t[0]) / static_cast<double>(n - 1);

  // ---- Trim (Table 2.4): the longest still hover without a chirp, after 2 s of settling.
  {
    const auto &u = log.Column("u"), &v = log.Column("v"), &w = log.Column("w");
    std::size_t best0 = 0, best1 = 0;
    for (std::size_t i = 0; i < n;) {
      auto ok = [&](std::size_t k) {
        return task[k] == 2 && chirp[k] == 0 && armed[k] == 1 && std::hypot(u[k], v[k], w[k]) < 0.3;
      };
      if (!ok(i)) { ++i; continue; }
      std::size_t j = i;
      while (j < n && ok(j)) ++j;
      if (j - i > best1 - best0) best0 = i, best1 = j;
      i = j;
    }
    const auto settle = static_cast<std::size_t>(std::lround(2.0 / dt));
    if (best1 - best0 >= settle + static_cast<std::size_t>(std::lround(5.0 / dt))) {
      best0 += settle;
      id.trim.found = true;
      id.trim.t0 = t[best0];
      id.trim.t1 = t[best1 - 1];
      const std::pair<const char*, const char*> names[] = {
          {"u_a0", "Ua"}, {"u_e0", "Ue"}, {"u_th0", "Uth"}, {"u_r0", "Ur"}, {"u0", "u"},     {"v0", "v"},
          {"w0", "w"},    {"phi0", "phi"}, {"theta0", "theta"}, {"psi0", "psi"}, {"p0", "p"}, {"q0", "q"},
          {"r0", "r"},    {"acx0", "acx"}, {"acy0", "acy"}, {"acz0", "acz"}};
      for (const auto& [key, column] : names) {
        const auto& c = log.Column(column);
        double sum = 0;
        for (std::size_t k = best0; k < best1; ++k) sum += c[k];
        id.trim.values[key] = sum / static_cast<double>(best1 - best0);
      }
    } else {
      id.notes.push_back("no hover of at least 7 s without a chirp: no trim values");
    }
  }

  // ---- Chirp segments, each with 0.5 s of hover before and 1.5 s after (the response decays).
  for (std::size_t i = 0; i < n;) {
    if (chirp[i] == 0) { ++i; continue; }
    std::size_t j = i;
    while (j < n && chirp[j] == chirp[i] && mode[j] == mode[i]) ++j;
    const int channel = static_cast<int>(chirp[i]);
    const int wiring = static_cast<int>(mode[i]);
    const std::size_t i0 = i >= 25 ? i - 25 : 0;
    std::size_t i1 = std::min(n, j + 75);
    for (std::size_t k = j; k < i1; ++k)
      if (chirp[k] != 0 || mode[k] != mode[i]) { i1 = k; break; }
    const double seg_t0 = t[i0], seg_t1 = t[i1 - 1];
    i = j;
    if (i1 - i0 < 250) {
      id.notes.push_back("chirp at t = " + std::to_string(seg_t0) + " s is shorter than 5 s: skipped");
      continue;
    }
    auto base = [&](const char* model, const char* eq, const char* output) {
      ModelFit f;
      f.model = model;
      f.equation = eq;
      f.output_name = output;
      f.t0 = seg_t0;
      f.t1 = seg_t1;
      f.t = Slice(t, i0, i1);
      return f;
    };
    if (channel == kThrottle) {
      // Eq. 2.13 with the thrust of Eq. 2.15: the accelerometer's z axis measures
      // -sum(f_i)/m (plus a small drag) whatever the attitude. Input: the mean rotor input.
      std::vector<double> u(i1 - i0), y(i1 - i0);
      const auto &m1 = log.Column("M1"), &m2 = log.Column("M2"), &m3 = log.Column("M3"), &m4 = log.Column("M4");
      const auto& acz = log.Column("acz");
      for (std::size_t k = i0; k < i1; ++k) {
        u[k - i0] = (m1[k] + m2[k] + m3[k] + m4[k]) / 4.0;
        y[k - i0] = -known.mass * acz[k];
      }
      const LagModel m = FitLag(u, y, dt, 1, true, 0.0);
      ModelFit f = base("rotor_thrust", "Eq. 2.13", "total thrust -m acz [N]");
      f.params = {{"Kf", m.gain / 4.0}, {"tau_f", m.tau}, {"u_zero_thrust", -m.offset / m.gain}};
      f.measured = y;
      f.predicted = m.predicted;
      f.fit_percent = FitPercent(y, m.predicted);
      id.fits.push_back(std::move(f));
    } else if (wiring == kDirect && channel == kRudder) {
      // Eq. 2.16: r' = (Jxx - Jyy)/Jzz p q + d/Jzz Omega, Omega = K_v/(1 + tau_f s) sum (-1)^(i+1) v_i.
      // The log's rates are means over each 20 ms (the IMU integrates), so the difference of two
      // successive ones is the double integral of r' over the rows: linear in d/Jzz.
      const auto &m1 = log.Column("M1"), &m2 = log.Column("M2"), &m3 = log.Column("M3"), &m4 = log.Column("M4");
      const auto &p = log.Column("p"), &q = log.Column("q"), &r = log.Column("r");
      const double coupling = (known.inertia.x() - known.inertia.y()) / known.inertia.z();
      std::vector<double> v(i1 - i0);
      for (std::size_t k = i0; k < i1; ++k) v[k - i0] = m1[k] - m2[k] + m3[k] - m4[k];
      double theta = 0, c = 0, tau_best = 0;
      auto regress = [&](double tau, double* th, double* off) {
        // Sub-step integral I of the lagged input, then D_k = mean over row k of I(s + dt) - I(s).
        const double h = dt / kSubsteps, a = std::exp(-h / tau);
        std::vector<double> I(v.size() * kSubsteps + 1, 0.0);
        double x = v[0];
        for (std::size_t j = 0; j + 1 < I.size(); ++j) {
          x = a * x + (1 - a) * v[j / kSubsteps];
          I[j + 1] = I[j] + x * h;
        }
        std::vector<double> D, dr;
        for (std::size_t k = 1; k + 1 < v.size(); ++k) {
          double sum = 0;
          for (int s = 0; s < kSubsteps; ++s) {
            const std::size_t j = (k - 1) * kSubsteps + s;
            sum += I[j + kSubsteps] - I[j];
          }
          D.push_back(sum / kSubsteps);
          const std::size_t g = i0 + k;
          dr.push_back(r[g + 1] - r[g] - coupling * p[g] * q[g] * dt);
        }
        return FitGainOffset(D, dr, th, off);
      };
      const double log_tau = GoldenMin([&](double lt) { double a, b; return regress(std::exp(lt), &a, &b); },
                                       std::log(0.005), std::log(1.0));
      tau_best = std::exp(log_tau);
      regress(tau_best, &theta, &c);
      ModelFit f = base("yaw_torque", "Eq. 2.16", "yaw rate r [rad/s]");
      f.params = {{"d", theta * known.inertia.z() / known.rotor_speed_gain}, {"tau_f", tau_best}};
      // For the picture: the model's yaw rate, integrated from the first measured one.
      f.measured = Slice(r, i0, i1);
      const auto lag = SimulateLag(v, dt, tau_best, 1, 0.0, true);
      f.predicted.assign(v.size(), f.measured[0]);
      for (std::size_t k = 1; k < v.size(); ++k)
        f.predicted[k] = f.predicted[k - 1] + (theta * lag[k] + c / dt) * dt;
      // The fit of what was regressed: the row-to-row change of r.
      std::vector<double> dy, dyhat;
      for (std::size_t k = 1; k < v.size(); ++k) dy.push_back(f.measured[k] - f.measured[k - 1]), dyhat.push_back(f.predicted[k] - f.predicted[k - 1]);
      f.fit_percent = FitPercent(dy, dyhat);
      id.fits.push_back(std::move(f));
    } else if (wiring == kGyroCruise || (wiring == kGyroHover && channel == kRudder)) {
      // Eq. 2.20-2.22 (and 2.19): body rate first order in its channel. Rates are 20 ms means.
      const char* input = channel == kAileron ? "Ua" : channel == kElevator ? "Ue" : "Ur";
      const char* output = channel == kAileron ? "p" : channel == kElevator ? "q" : "r";
      const char* axis = channel == kAileron ? "p" : channel == kElevator ? "q" : "r";
      const auto u = Slice(log.Column(input), i0, i1), y = Slice(log.Column(output), i0, i1);
      const LagModel m = FitLag(u, y, dt, 1, true, 0.0);
      ModelFit f = base(channel == kRudder ? "yaw_rate_gyro" : wiring == kGyroCruise ? "body_rate_gyro_cruise" : "",
                        channel == kAileron ? "Eq. 2.20" : channel == kElevator ? "Eq. 2.21" : "Eq. 2.19, 2.22",
                        output);
      f.params = {{std::string("K_") + axis, m.gain}, {std::string("tau_") + axis, m.tau}};
      f.measured = y;
      f.predicted = m.predicted;
      f.fit_percent = FitPercent(y, m.predicted);
      id.fits.push_back(std::move(f));
    } else if (wiring == kGyroHover) {
      // Eq. 2.17-2.18: angle = K / (1 + tau s)^2 e^(-T s) u; angles are instantaneous.
      const bool roll = channel == kAileron;
      const auto u = Slice(log.Column(roll ? "Ua" : "Ue"), i0, i1);
      const auto y = Slice(log.Column(roll ? "phi" : "theta"), i0, i1);
      const LagModel m = FitLag(u, y, dt, 2, false, 0.3);
      ModelFit f = base("attitude_gyro_hover", roll ? "Eq. 2.17" : "Eq. 2.18", roll ? "phi" : "theta");
      const std::string a = roll ? "phi" : "theta";
      f.params = {{"K_" + a, m.gain}, {"tau_" + a, m.tau}, {"T_" + a, m.delay}};
      f.measured = y;
      f.predicted = m.predicted;
      f.fit_percent = FitPercent(y, m.predicted);
      id.fits.push_back(std::move(f));
    } else {
      id.notes.push_back("chirp on channel " + std::to_string(channel) + " at t = " + std::to_string(seg_t0) +
                         " s in direct wiring: no model structure identifies it (the roll and pitch inertias "
                         "are measured on the ground, Table 2.2)");
    }
  }
  if (id.fits.empty()) id.notes.push_back("no chirp segments of at least 5 s in the log");
  return id;
}

std::string ToJson(const Identification& id) {
  nlohmann::ordered_json j;
  if (id.trim.found) {
    j["trim"]["t0_s"] = id.trim.t0;
    j["trim"]["t1_s"] = id.trim.t1;
    for (const auto& [k, v] : id.trim.values) j["trim"]["values"][k] = v;
  } else {
    j["trim"] = nullptr;
  }
  j["models"] = nlohmann::ordered_json::array();
  for (const auto& f : id.fits) {
    nlohmann::ordered_json m;
    m["model"] = f.model;
    m["equation"] = f.equation;
    m["t0_s"] = f.t0;
    m["t1_s"] = f.t1;
    m["output"] = f.output_name;
    for (const auto& [k, v] : f.params) m["params"][k] = v;
    m["fit_percent"] = f.fit_percent;
    j["models"].push_back(m);
  }
  j["notes"] = id.notes;
  return j.dump(2);
}

}  // namespace uav::sysid

#include "app/cli/init.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "analysis/common/summary.h"
#include "app/cli/exit_codes.h"
#include "app/cli/output_folder.h"
#include "app/core/campaign.h"
#include "app/core/checked_write.h"
#include "app/core/signals.h"
#include "app/core/yaml_load.h"
#include "app/formats/frf_text.h"
#include "app/formats/matfile.h"
#include "app/formats/uff58.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.10g", v);
  return buf;
}

std::string sig(double v, int digits) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
  return buf;
}

// A YAML scalar: plain when it is safe to read back as the same string, else double-quoted.
std::string yaml_plain_or_quoted(const std::string& s) {
  const bool plain = !s.empty() &&
                     std::all_of(s.begin(), s.end(),
                                 [](char c) {
                                   return std::isalnum(static_cast<unsigned char>(c)) || c == '_' ||
                                          c == '-' || c == '.' || c == '/';
                                 }) &&
                     !std::isdigit(static_cast<unsigned char>(s[0])) && s[0] != '-';
  if (plain) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// Always double-quoted: a quoted `column` value is header text, never an index.
std::string yaml_quoted(const std::string& s) {
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// ---- The YAML text of a proposed file, a comment per guess --------------------------------

class YamlText {
 public:
  void line(const std::string& text, const std::string& why = "") { lines_.push_back({text, why}); }
  void comment(const std::string& text) { lines_.push_back({"", text}); }
  void todo(const std::string& text) { lines_.push_back({"", "TODO " + text}); }
  std::string str() const {
    std::string out;
    for (const auto& [text, why] : lines_) {
      if (text.empty()) {
        out += "# " + why + "\n";
      } else if (why.empty()) {
        out += text + "\n";
      } else {
        std::string t = text;
        if (t.size() < 36) t.resize(36, ' ');
        out += t + "  # " + why + "\n";
      }
    }
    return out;
  }

 private:
  std::vector<std::pair<std::string, std::string>> lines_;
};

// ---- Column names ----------------------------------------------------------------------------

// A channel (column, UFF record, .mat variable) name taken apart: the unit in a trailing (...) or
// [...], the words before it, lower case.
struct Col {
  std::string name;
  std::string unit;  // lower case, blanks removed ("m/s^2"); empty when none
  std::vector<std::string> tokens;
  std::string compact;  // the tokens joined
};

Col describe(const std::string& name) {
  Col c;
  c.name = name;
  std::string base = name;
  while (!base.empty() && base.back() == ' ') base.pop_back();
  if (!base.empty() && (base.back() == ')' || base.back() == ']')) {
    const char open = base.back() == ')' ? '(' : '[';
    const std::size_t o = base.rfind(open);
    if (o != std::string::npos) {
      for (const char ch : base.substr(o + 1, base.size() - o - 2)) {
        if (ch != ' ') c.unit += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      }
      base.erase(o);
    }
  }
  std::string word;
  for (const char ch : base + " ") {
    if (std::isalnum(static_cast<unsigned char>(ch))) {
      word += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    } else if (!word.empty()) {
      c.tokens.push_back(word);
      c.compact += word;
      word.clear();
    }
  }
  return c;
}

bool any_of_words(const std::string& s, std::initializer_list<const char*> words) {
  return std::any_of(words.begin(), words.end(), [&](const char* w) { return s == w; });
}

bool contains_any(const std::string& s, std::initializer_list<const char*> parts) {
  return std::any_of(parts.begin(), parts.end(),
                     [&](const char* p) { return s.find(p) != std::string::npos; });
}

bool is_time(const Col& c) {
  return any_of_words(c.compact, {"t", "time", "times", "timestamp", "xvalue", "zeit", "temps",
                                  "tiempo", "timesec", "ts"}) ||
         (!c.tokens.empty() && c.tokens.front() == "time");
}

bool is_hammer(const Col& c) {
  return contains_any(c.compact, {"hammer", "impact"}) ||
         any_of_words(c.compact, {"force", "f", "kraft", "excitation", "load", "input"});
}

bool is_response(const Col& c) {
  for (const auto& t : c.tokens) {
    if (t.rfind("acc", 0) == 0 || t.rfind("resp", 0) == 0 || t.rfind("vel", 0) == 0 ||
        t.rfind("disp", 0) == 0 || t.rfind("beschl", 0) == 0 || t == "output" || t == "a" ||
        t == "v") {
      return true;
    }
  }
  return false;
}

// Fx, F_x, Force X, force_x, Kraft X: a force along one axis.
bool is_axis_force(const Col& c, char axis) {
  const std::string a(1, axis);
  return c.compact == "f" + a || c.compact == "force" + a || c.compact == a + "force" ||
         c.compact == "kraft" + a;
}

bool is_pulse(const Col& c) {
  return contains_any(c.compact, {"tach", "zero", "pulse", "trigger", "index", "keyphas", "opr",
                                  "oncerev", "laser", "encoder", "ttl"});
}

// x, dx, defl x, cap_x, sensor x, x (mm): a deflection sensor along one axis.
bool is_deflection(const Col& c, char axis) {
  const std::string a(1, axis);
  if (c.compact == a) return true;
  std::string rest;
  if (c.compact.size() > 1 && c.compact.back() == axis) {
    rest = c.compact.substr(0, c.compact.size() - 1);
  } else if (c.compact.size() > 1 && c.compact.front() == axis) {
    rest = c.compact.substr(1);
  } else {
    return false;
  }
  return any_of_words(rest, {"d", "defl", "deflection", "cap", "capacitive", "sensor", "probe",
                             "disp", "displacement", "gap", "prox", "proximity", "eddy", "pos"});
}

// ---- Units: the scale that makes a column the unit a kind needs ------------------------------

struct Scale {
  double factor = 1.0;  // 1: none
  std::string why;      // the comment
  std::string todo;     // a unit no factor converts (volts): what to set
};

Scale force_scale(const Col& c) {
  Scale s;
  if (c.unit == "kn") {
    s = {1000.0, "the header says kN; the test needs N", ""};
  } else if (c.unit == "lbf") {
    s = {4.4482216152605, "the header says lbf; the test needs N", ""};
  } else if (c.unit == "v" || c.unit == "mv") {
    s.todo = "the column is in " + c.unit + "; the test needs N (the sensor's N/V)";
  }
  return s;
}

Scale length_scale(const Col& c) {
  Scale s;
  if (c.unit == "mm") {
    s = {1e-3, "the header says mm; the test needs m", ""};
  } else if (c.unit == "um" || c.unit == "\xc2\xb5m" || c.unit == "\xce\xbcm" ||
             c.unit == "micron") {
    s = {1e-6, "the header says um; the test needs m", ""};
  } else if (c.unit == "v" || c.unit == "mv") {
    s.todo = "the column is in " + c.unit + "; the test needs m (the sensor's m/V)";
  }
  return s;
}

// The `response:` of a tap test from the response column's unit, else its name.
struct ResponseGuess {
  std::string kind;  // acceleration | velocity | displacement; empty: not decided
  double factor = 1.0;
  std::string why;
};

ResponseGuess response_of(const Col& c) {
  std::string u;
  for (const char ch : c.unit) {
    if (ch != '^' && ch != '(' && ch != ')') u += ch;
  }
  if (u == "m/s2" || u == "m/s\xc2\xb2" || u == "ms-2" || u == "m/s/s") {
    return {"acceleration", 1.0, "the unit m/s^2 of '" + c.name + "'"};
  }
  if (u == "g") return {"acceleration", 9.80665, "the unit g of '" + c.name + "'"};
  if (u == "mm/s2") return {"acceleration", 1e-3, "the unit mm/s^2 of '" + c.name + "'"};
  if (u == "m/s") return {"velocity", 1.0, "the unit m/s of '" + c.name + "'"};
  if (u == "mm/s") return {"velocity", 1e-3, "the unit mm/s of '" + c.name + "'"};
  if (u == "m") return {"displacement", 1.0, "the unit m of '" + c.name + "'"};
  if (u == "mm") return {"displacement", 1e-3, "the unit mm of '" + c.name + "'"};
  if (u == "um" || u == "\xc2\xb5m") {
    return {"displacement", 1e-6, "the unit um of '" + c.name + "'"};
  }
  if (u.empty()) {
    for (const auto& t : c.tokens) {
      if (t.rfind("acc", 0) == 0 || t.rfind("beschl", 0) == 0 || t == "a") {
        return {"acceleration", 1.0, "the name '" + c.name + "' (no unit stated: m/s^2 assumed)"};
      }
      if (t.rfind("vel", 0) == 0 || t == "v") {
        return {"velocity", 1.0, "the name '" + c.name + "' (no unit stated: m/s assumed)"};
      }
      if (t.rfind("disp", 0) == 0) {
        return {"displacement", 1.0, "the name '" + c.name + "' (no unit stated: m assumed)"};
      }
    }
  }
  return {};
}

// The ordinate of an FRF per newton from a column unit ("m/s^2/N", "(m/s)/N", "m/N") or a word
// of the header line (accelerance, mobility, receptance).
std::string frf_ordinate(const std::string& unit_or_text) {
  std::string u;
  for (const char ch : lower(unit_or_text)) {
    if (ch != '^' && ch != '(' && ch != ')' && ch != ' ') u += ch;
  }
  if (contains_any(u, {"m/s2/n", "m/s\xc2\xb2/n", "accelerance", "inertance"})) {
    return "acceleration";
  }
  if (contains_any(u, {"m/s/n", "m/ns", "mobility"})) return "velocity";
  if (contains_any(u, {"m/n", "receptance", "compliance", "dynamicflexibility"})) {
    return "displacement";
  }
  return "";
}

// x or y from the words of a path and names (tap-x, hits_y, "Accel X"); empty when neither or
// both.
std::string axis_from_words(const std::vector<std::string>& texts, std::string* where) {
  std::set<std::string> found;
  std::string from;
  for (const auto& text : texts) {
    for (const auto& t : describe(text).tokens) {
      std::string a;
      if (t == "x" || t == "y") {
        a = t;
      } else if (t.size() > 1 && (t.back() == 'x' || t.back() == 'y') &&
                 any_of_words(t.substr(0, t.size() - 1), {"tap", "hit", "dir", "axis", "hammer"})) {
        a = t.substr(t.size() - 1);
      }
      if (!a.empty() && found.insert(a).second && from.empty()) from = text;
    }
  }
  if (found.size() != 1) return "";
  if (where) *where = from;
  return *found.begin();
}

// ---- Signals: sample rate and pulse rate -----------------------------------------------------

struct Rate {
  double hz = 0.0;
  std::string why;
  std::string todo;  // the reason no rate was taken
};

// The rate of an evenly stepped time vector (in `unit_factor` seconds per unit).
Rate rate_from_time(const Eigen::VectorXd& t, double unit_factor, const std::string& what) {
  Rate r;
  const Eigen::Index n = t.size();
  if (n < 3) {
    r.todo = what + " has fewer than 3 samples";
    return r;
  }
  const double dt = (t(n - 1) - t(0)) / static_cast<double>(n - 1);
  if (!(dt > 0)) {
    r.todo = what + " does not increase";
    return r;
  }
  double worst = 0.0;
  for (Eigen::Index i = 1; i < n; ++i) worst = std::max(worst, std::abs(t(i) - t(i - 1) - dt));
  if (worst > 1e-3 * dt) {
    r.todo = what + " is not evenly stepped (a step differs from the mean " + sig(dt, 6) + " by " +
             sig(worst, 3) + ")";
    return r;
  }
  double hz = 1.0 / (dt * unit_factor);
  if (std::abs(hz - std::round(hz)) < 1e-6 * hz) hz = std::round(hz);
  r.hz = hz;
  r.why = "from " + what + ": " + std::to_string(n) + " samples " + sig(dt, 8) +
          (unit_factor == 1.0    ? " s"
           : unit_factor == 1e-3 ? " ms"
                                 : " us") +
          " apart";
  return r;
}

double time_unit_factor(const Col& c) {
  if (c.unit == "ms") return 1e-3;
  if (c.unit == "us" || c.unit == "\xc2\xb5s") return 1e-6;
  return 1.0;
}

// Revolutions from a once-per-revolution pulse: rising edges through the midpoint of its low
// and high levels.
struct Rpm {
  double rpm = 0.0;
  std::string why;
};

Rpm rpm_from_pulse(const Eigen::VectorXd& v, double fs, const std::string& name) {
  Rpm r;
  if (v.size() < 3 || !(fs > 0)) return r;
  const double lo = v.minCoeff(), hi = v.maxCoeff();
  if (!(hi > lo)) return r;
  const double mid = 0.5 * (lo + hi);
  std::vector<Eigen::Index> edges;
  for (Eigen::Index i = 1; i < v.size(); ++i) {
    if (v(i - 1) < mid && v(i) >= mid) edges.push_back(i);
  }
  if (edges.size() < 3) return r;
  const double period = static_cast<double>(edges.back() - edges.front()) / (edges.size() - 1) / fs;
  for (std::size_t k = 1; k < edges.size(); ++k) {
    const double p = static_cast<double>(edges[k] - edges[k - 1]) / fs;
    if (std::abs(p - period) > 0.02 * period) return r;  // not one steady speed
  }
  r.rpm = 60.0 / period;
  r.why = "from the pulse '" + name + "': " + std::to_string(edges.size()) +
          " rising edges, one every " + sig(period, 6) + " s";
  return r;
}

// ---- Reading a file through the project's readers --------------------------------------------

std::string short_error(std::string what, const std::string& label) {
  if (what.rfind(label + ": ", 0) == 0) what = what.substr(label.size() + 2);
  return what;
}

// The dialect keys a SignalTable message proposes ("...; the file looks like ...: set
// data.delimiter: ";" and data.decimal: ","").
std::optional<DataSpec> dialect_from_message(const std::string& message, DataSpec data) {
  const std::size_t looks = message.find("; the file looks like ");
  if (looks == std::string::npos) return std::nullopt;
  const std::size_t set = message.find(": set ", looks);
  if (set == std::string::npos) return std::nullopt;
  const std::string keys = message.substr(set + 6);
  bool any = false;
  if (const auto p = keys.find("data.delimiter: "); p != std::string::npos) {
    const std::string v = keys.substr(p + 16);
    if (v.rfind("tab", 0) == 0) {
      data.delimiter = '\t';
    } else if (v.size() >= 3 && v[0] == '"') {
      data.delimiter = v[1];
    } else {
      return std::nullopt;
    }
    any = true;
  }
  if (const auto p = keys.find("data.decimal: \""); p != std::string::npos) {
    data.decimal = keys[p + 15];
    any = true;
  }
  if (const auto p = keys.find("data.skip_lines: "); p != std::string::npos) {
    data.skip_lines = std::atoi(keys.c_str() + p + 17);
    any = true;
  }
  if (!any) return std::nullopt;
  return data;
}

// A LabVIEW header block's sampling step ("Delta_X<TAB>3.906250E-5") in the lines before the
// header row.
std::optional<double> labview_delta_x(const fs::path& file, int skip_lines) {
  std::ifstream in(file);
  std::string line;
  for (int i = 0; i < skip_lines && std::getline(in, line); ++i) {
    if (line.rfind("Delta_X", 0) != 0) continue;
    std::istringstream s(line.substr(7));
    std::string cell;
    while (s >> cell) {
      try {
        std::size_t used = 0;
        const double v = std::stod(cell, &used);
        if (used == cell.size() && v > 0) return v;
      } catch (const std::exception&) {
      }
    }
  }
  return std::nullopt;
}

// ---- One proposed test ----------------------------------------------------------------------

// A channel a kind needs, the column feeding it and the reason.
struct Mapping {
  std::string channel;
  std::string column;  // empty: no column found
  double scale = 1.0;
  std::string why;
  std::string todo;
};

struct TestGuess {
  std::string kind;  // empty: not decided
  std::string kind_why;
  std::string kind_todo;
  std::vector<Mapping> channels;
  std::vector<std::pair<std::string, std::string>> keys;  // key text, comment (after the kind)
  std::vector<std::string> todos;                         // keys not decided
};

// The reading of one data file.
struct FileLook {
  std::vector<std::string> names;  // channel names (text header, UFF id1, .mat variables)
  Rate rate;
  DataSpec data;  // the dialect that reads the file
  std::optional<SignalTable> table;
};

// Picks the first column (not used yet) that `pred` accepts.
std::optional<std::size_t> pick(const std::vector<Col>& cols, std::vector<bool>& used,
                                const std::function<bool(const Col&)>& pred) {
  for (std::size_t i = 0; i < cols.size(); ++i) {
    if (!used[i] && pred(cols[i])) {
      used[i] = true;
      return i;
    }
  }
  return std::nullopt;
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "'" : ", '") + n + "'";
  return s;
}

// The kind, its channels and keys from the names of the channels and what the record holds.
TestGuess guess_test(const FileLook& look, const std::vector<std::string>& path_words,
                     const std::string& uff_axis) {
  TestGuess g;
  std::vector<Col> cols;
  for (const auto& n : look.names) cols.push_back(describe(n));
  std::vector<bool> used(cols.size(), false);
  for (std::size_t i = 0; i < cols.size(); ++i) used[i] = is_time(cols[i]);

  const auto col_of = [&](const std::string& channel, std::optional<std::size_t> i,
                          const std::string& role) {
    Mapping m;
    m.channel = channel;
    if (i) {
      m.column = cols[*i].name;
      m.why = "recognised as the " + role;
    } else {
      m.todo = "channels." + channel + ".column: no column looks like the " + role + " (" +
               quoted_list(look.names) + ")";
    }
    return m;
  };
  const auto add_scale = [](Mapping& m, const Scale& s) {
    if (s.factor != 1.0) {
      m.scale = s.factor;
      m.why += "; " + s.why;
    }
    if (!s.todo.empty()) m.todo = "channels." + m.channel + ".scale: " + s.todo;
  };
  const auto rpm_key = [&](const Mapping* pulse) {
    Rpm rpm;
    if (pulse && !pulse->column.empty() && look.table && look.rate.hz > 0) {
      rpm = rpm_from_pulse(look.table->channel(pulse->column), look.rate.hz, pulse->column);
    }
    if (rpm.rpm > 0) {
      g.keys.push_back({"spindle_rpm: " + sig(rpm.rpm, 6), rpm.why});
    } else {
      g.todos.push_back(
          "spindle_rpm: the spindle speed, rpm (not found from a steady once-per-revolution "
          "pulse)");
    }
  };
  const auto axis_key = [&](const std::vector<std::string>& extra_words) {
    std::string where;
    std::vector<std::string> words = path_words;
    words.insert(words.end(), extra_words.begin(), extra_words.end());
    std::string axis = uff_axis;
    if (!axis.empty()) {
      where = "the record's response direction";
    } else {
      axis = axis_from_words(words, &where);
      if (!axis.empty()) where = "the name '" + where + "'";
    }
    if (!axis.empty()) {
      g.keys.push_back({"axis: " + axis, "from " + where});
    } else {
      g.todos.push_back(
          "axis: x or y, the direction of the hit and of the response (neither the file's nor "
          "its folder's name says it)");
    }
  };

  const std::vector<std::string> washers = {"x1", "x2", "y1", "y2", "z1", "z2"};
  const bool all_washers = std::all_of(washers.begin(), washers.end(), [&](const std::string& w) {
    return std::any_of(cols.begin(), cols.end(), [&](const Col& c) { return c.compact == w; });
  });
  const auto has = [&](const std::function<bool(const Col&)>& pred) {
    for (std::size_t i = 0; i < cols.size(); ++i) {
      if (!used[i] && pred(cols[i])) return true;
    }
    return false;
  };
  const auto fx = [](const Col& c) { return is_axis_force(c, 'x'); };
  const auto fy = [](const Col& c) { return is_axis_force(c, 'y'); };
  const auto dx = [](const Col& c) { return is_deflection(c, 'x'); };
  const auto dy = [](const Col& c) { return is_deflection(c, 'y'); };

  if (all_washers) {
    std::vector<Mapping> w;
    for (const auto& name : washers) {
      w.push_back(col_of(name, pick(cols, used, [&](const Col& c) { return c.compact == name; }),
                         "washer channel"));
    }
    if (has(is_hammer)) {
      g.kind = "sifs-tap";
      Mapping h = col_of("hammer", pick(cols, used, is_hammer), "hammer force");
      add_scale(h, force_scale(describe(h.column)));
      g.kind_why = "the six washer channels x1 .. z2 and a hammer column '" + h.column + "'";
      g.channels.push_back(h);
      g.channels.insert(g.channels.end(), w.begin(), w.end());
      axis_key({h.column});
      g.keys.push_back({"hits: auto", "the default: hits found on the hammer"});
      g.todos.push_back("band_hz: [low, high], the modal fit band, Hz");
    } else {
      g.kind_todo =
          "kind: sifs-static (known loads) or sifs-cut (a compensated cut): the six washer "
          "channels x1 .. z2 and no hammer column";
      g.channels = w;
    }
  } else if (has(fx) && has(fy)) {
    g.kind = "dyno-slot";
    Mapping mx = col_of("Fx", pick(cols, used, fx), "force along x");
    Mapping my = col_of("Fy", pick(cols, used, fy), "force along y");
    add_scale(mx, force_scale(describe(mx.column)));
    add_scale(my, force_scale(describe(my.column)));
    Mapping z = col_of("zero", pick(cols, used, is_pulse), "zero-count pulse");
    g.kind_why = "force columns '" + mx.column + "' and '" + my.column + "'" +
                 (z.column.empty() ? "" : " and a pulse '" + z.column + "'");
    g.channels = {mx, my, z};
    rpm_key(&g.channels.back());
    g.todos.push_back("feed_per_tooth_mm: the feed per tooth, mm");
    g.todos.push_back("axial_depth_mm: the axial depth of the slot, mm");
  } else if (has(is_pulse) && has(dx) && has(dy)) {
    g.kind = "cut";
    Mapping tach = col_of("tach", pick(cols, used, is_pulse), "tachometer pulse");
    Mapping mx = col_of("x", pick(cols, used, dx), "deflection along x");
    Mapping my = col_of("y", pick(cols, used, dy), "deflection along y");
    add_scale(mx, length_scale(describe(mx.column)));
    add_scale(my, length_scale(describe(my.column)));
    g.kind_why = "deflection columns '" + mx.column + "' and '" + my.column +
                 "' and a tachometer pulse '" + tach.column + "'";
    g.channels = {mx, my, tach};
    g.todos.push_back("operation: up-milling or down-milling");
    rpm_key(&g.channels.back());
    g.todos.push_back("feed_per_tooth_mm: the feed per tooth, mm");
    g.todos.push_back("radial_immersion_mm: the radial immersion, mm");
    g.todos.push_back("axial_depth_mm: the depth, mm, or [start, end] for a ramp");
    g.todos.push_back("cut_window_s: [start, end], s, when the tool is in the workpiece");
  } else if (has([](const Col& c) { return c.compact == "cycle"; }) &&
             has([](const Col& c) { return c.compact == "power"; })) {
    g.kind = "grinding";
    g.kind_why = "the columns 'cycle' and 'power' of a series of grinding cycles";
    const std::vector<std::pair<std::string, std::string>> chans = {
        {"cycle", "cycle"}, {"u_mm_s", "umms"}, {"power", "power"}, {"Dw_mm", "dwmm"}};
    for (const auto& [name, compact] : chans) {
      const std::string cp = compact;
      g.channels.push_back(
          col_of(name, pick(cols, used, [&](const Col& c) { return c.compact == cp; }), name));
    }
    g.todos.push_back("model: the grinding model (docs/format/test-kinds.md#kind-grinding)");
    g.todos.push_back("noise: the measurement standard deviations");
    g.todos.push_back("filter: P0 and Q of the filters");
  } else if (has(is_hammer) && has(is_response)) {
    g.kind = "tap";
    Mapping f = col_of("force", pick(cols, used, is_hammer), "force");
    add_scale(f, force_scale(describe(f.column)));
    Mapping r = col_of("response", pick(cols, used, is_response), "response");
    g.kind_why = "a force column '" + f.column + "' and a response column '" + r.column + "'";
    axis_key({r.column});
    const ResponseGuess rg = response_of(describe(r.column));
    if (!rg.kind.empty()) {
      g.keys.push_back({"response: " + rg.kind, "from " + rg.why});
      if (rg.factor != 1.0) {
        r.scale = rg.factor;
        r.why += "; scaled to SI";
      }
    } else {
      g.todos.push_back("response: acceleration, velocity or displacement (the column '" +
                        r.column + "' states no unit chatterlab knows)");
    }
    g.keys.push_back({"hits: auto", "the default: hits found on the force channel"});
    g.channels = {f, r};
  } else {
    g.kind_todo =
        "kind: no kind's channels recognised among " + quoted_list(look.names) +
        " (tap: a force and a response; dyno-slot: Fx, Fy and a zero pulse; cut: x, y and a "
        "tachometer; grinding: cycle, power; sifs: x1 .. z2); set the kind and "
        "channels.<name>.column";
  }
  return g;
}

// ---- The folder -------------------------------------------------------------------------------

bool is_text_frf_only(const fs::path& p) {
  const std::string e = lower(p.extension().string());
  return e == ".dat" || e == ".asc" || e == ".frf";
}

bool is_data_file(const fs::path& p) {
  const std::string e = lower(p.extension().string());
  return is_text_signal_file(p) || is_text_frf_only(p) || e == ".uff" || e == ".unv" ||
         e == ".mat" || e == ".f32" || e == ".f64";
}

std::string safe_name(const std::string& s) {
  std::string out;
  for (const char c : s) {
    out +=
        std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' ? c : '-';
  }
  while (!out.empty() && out.front() == '.') out.erase(0, 1);
  return out.empty() ? "test" : out;
}

std::string rel(const fs::path& p, const fs::path& root) {
  const std::string r = p.lexically_relative(root).generic_string();
  return r == "." ? "" : r;
}

// The files named by existing test.yaml files (data.file, frf.file, inspections.file) and by
// the campaign's truth.yaml.
std::set<fs::path> described_files(const fs::path& root, const std::vector<fs::path>& yamls) {
  std::set<fs::path> out;
  for (const auto& y : yamls) {
    try {
      std::vector<std::string> refused;  // a refused test.yaml names no file
      const YAML::Node n = load_yaml_file(y, y.filename().string(), &refused);
      if (!n || !n.IsMap()) continue;
      for (const char* key : {"data", "frf", "inspections"}) {
        if (n[key] && n[key].IsMap() && n[key]["file"] && n[key]["file"].IsScalar()) {
          const fs::path f =
              (y.parent_path() / n[key]["file"].as<std::string>()).lexically_normal();
          out.insert(f);
        }
      }
    } catch (const std::exception&) {
    }
  }
  // truth.yaml names files of known values (a synthetic campaign's trajectories): not tests.
  std::error_code ec;
  if (fs::is_regular_file(root / "truth.yaml", ec)) {
    try {
      std::vector<std::string> refused;
      std::vector<YAML::Node> todo = {load_yaml_file(root / "truth.yaml", "truth.yaml", &refused)};
      if (!todo.back()) todo.clear();
      while (!todo.empty()) {
        const YAML::Node n = todo.back();
        todo.pop_back();
        if (n.IsScalar()) {
          const std::string v = n.Scalar();
          if (v.size() < 512 && fs::is_regular_file(root / v, ec)) {
            out.insert((root / v).lexically_normal());
          }
        } else if (n.IsSequence()) {
          for (const auto& e : n) todo.push_back(e);
        } else if (n.IsMap()) {
          for (const auto& kv : n) todo.push_back(kv.second);
        }
      }
    } catch (const std::exception&) {
    }
  }
  return out;
}

// One test proposed for a data file (or one FRF record of it).
struct Unit {
  fs::path file;
  std::string suffix;  // "" or "-frf2" when a file gives several tests
  std::string finding;
  // The test.yaml text once the reference to the file (from its test folder) is known.
  std::function<std::string(const std::string& file_ref)> render;
  std::string kind;
};

// Reads a data file and makes its tests (or none, with the reason in `why_not`).
std::vector<Unit> look_at(const fs::path& file, const fs::path& root, std::string& why_not) {
  const std::string label = rel(file, root);
  const std::string ext = lower(file.extension().string());
  std::vector<std::string> path_words;
  for (const auto& part : fs::path(label).parent_path()) path_words.push_back(part.string());
  path_words.push_back(file.stem().string());

  std::vector<Unit> units;
  const auto frf_unit = [&](const std::string& ordinate, const std::string& ordinate_why,
                            const std::string& axis, const std::string& axis_why,
                            const std::string& columns_why, std::optional<int> record,
                            int records) {
    Unit u;
    u.file = file;
    u.kind = "tap";
    if (record && records > 1) u.suffix = "-frf" + std::to_string(*record);
    std::string axis_text = axis;
    std::string axis_from = axis_why;
    if (axis_text.empty()) {
      axis_text = axis_from_words(path_words, &axis_from);
      if (!axis_text.empty()) axis_from = "the name '" + axis_from + "'";
    }
    u.finding = "tap test from a measured FRF (" + columns_why + ")";
    u.render = [=](const std::string& ref) {
      YamlText y;
      y.line("kind: tap", "guessed: the file is an FRF (" + columns_why + ")");
      if (!axis_text.empty()) {
        y.line("axis: " + axis_text, "from " + axis_from);
      } else {
        y.todo(
            "axis: x or y, the direction of the hit and of the response (neither the file's "
            "nor its folder's name says it)");
      }
      if (!ordinate.empty()) {
        y.line("response: " + ordinate, "the FRF's ordinate per newton, from " + ordinate_why);
      } else {
        y.todo(
            "response: acceleration, velocity or displacement: the FRF's ordinate per newton "
            "(the file does not state it in a unit chatterlab knows)");
      }
      std::string f = "frf: {file: " + yaml_plain_or_quoted(ref);
      if (record && records > 1) f += ", record: " + std::to_string(*record);
      y.line(f + "}", record && records > 1
                          ? "FRF record " + std::to_string(*record) + " of " +
                                std::to_string(records) + " in the file"
                          : "no sample_rate_hz, data or hits with a measured FRF");
      return y.str();
    };
    units.push_back(std::move(u));
  };

  // A text FRF: read by the FRF reader; its columns named by a header line.
  const auto try_frf_text = [&](bool header_required) -> bool {
    try {
      const frf_text::FrfTable t = frf_text::read_frf_text(file, label);
      const bool by_header = t.columns.find("by the header") != std::string::npos;
      if (header_required && !by_header) return false;
      // The header line's text, for the ordinate's unit.
      std::string header_text;
      {
        const std::size_t at = t.columns.find("line ");
        const int line_no = at == std::string::npos ? 0 : std::atoi(t.columns.c_str() + at + 5);
        std::ifstream in(file);
        std::string line;
        for (int i = 1; i <= line_no && std::getline(in, line); ++i) {
          if (i == line_no) header_text = line;
        }
      }
      std::string ordinate = frf_ordinate(header_text);
      std::string why = ordinate.empty() ? "" : "the header '" + header_text + "'";
      frf_unit(ordinate, why, "", "",
               t.columns + ", " + std::to_string(t.f_hz.size()) + " frequencies, step " +
                   sig(t.df_hz, 6) + " Hz",
               std::nullopt, 1);
      return true;
    } catch (const InputError&) {
      return false;
    }
  };

  FileLook look;
  look.data.file = file;
  look.data.relative_file = file.filename().string();
  std::string uff_axis;

  if (ext == ".f32" || ext == ".f64") {
    why_not =
        "raw binary: the file names no channels and no sample rate; write its test.yaml by hand "
        "(data.channels, sample_rate_hz)";
    return units;
  }
  // Opens the file as a signal table into `look` (its channel names too); false, with the
  // reason in why_not, when it cannot be read.
  const auto open_table = [&]() {
    try {
      look.table = SignalTable::open(look.data, label);
    } catch (const InputError& e) {
      why_not = "not read: " + short_error(e.what(), label);
      return false;
    }
    look.names = look.table->names();
    return true;
  };
  if (is_text_frf_only(file)) {
    if (!try_frf_text(false))
      why_not = "not read as an FRF table (" + ext + " is read only as an FRF)";
    return units;
  }
  if (is_text_signal_file(file)) {
    try {
      look.table = SignalTable::open(look.data, label);
    } catch (const InputError& e) {
      const auto d = dialect_from_message(e.what(), look.data);
      bool read = false;
      if (d) {
        try {
          look.table = SignalTable::open(*d, label);
          look.data = *d;
          read = true;
        } catch (const InputError&) {
        }
      }
      if (!read) {
        if (try_frf_text(false)) return units;
        why_not = "not read: " + short_error(e.what(), label);
        return units;
      }
    }
    look.names = look.table->names();
    // A frequency column and a complex pair: an FRF table.
    std::vector<Col> cols;
    for (const auto& n : look.names) cols.push_back(describe(n));
    const auto named = [&](std::initializer_list<const char*> prefixes) {
      return std::any_of(cols.begin(), cols.end(), [&](const Col& c) {
        return std::any_of(prefixes.begin(), prefixes.end(), [&](const char* p) {
          return c.compact.rfind(p, 0) == 0 && !c.compact.empty();
        });
      });
    };
    const bool freq = std::any_of(cols.begin(), cols.end(), [](const Col& c) {
      return c.compact == "f" || c.compact == "fhz" || c.compact.rfind("freq", 0) == 0;
    });
    if (freq && ((named({"re"}) && named({"im"})) ||
                 (named({"mag", "abs", "amp"}) && named({"phase", "ph", "angle", "arg"})))) {
      if (try_frf_text(true)) return units;
    }
    // The sample rate: a time column, else a LabVIEW header block.
    for (const auto& c : cols) {
      if (!is_time(c)) continue;
      look.rate = rate_from_time(look.table->channel(c.name), time_unit_factor(c),
                                 "the time column '" + c.name + "'");
      break;
    }
    if (look.rate.hz == 0 && look.data.skip_lines > 0) {
      if (const auto dx = labview_delta_x(file, look.data.skip_lines)) {
        look.rate.hz = 1.0 / *dx;
        if (std::abs(look.rate.hz - std::round(look.rate.hz)) < 1e-6 * look.rate.hz) {
          look.rate.hz = std::round(look.rate.hz);
        }
        look.rate.why = "from the header block's Delta_X " + sig(*dx, 8) + " s";
      }
    }
    if (look.rate.hz == 0 && look.rate.todo.empty()) look.rate.todo = "no time column";
  } else if (ext == ".uff" || ext == ".unv") {
    std::vector<uff::Function58> functions;
    try {
      functions = uff::read_uff58(file);
    } catch (const InputError& e) {
      why_not = "not read: " + short_error(e.what(), file.string());
      return units;
    }
    int time_records = 0;
    std::vector<int> frf_records;  // index into functions
    for (std::size_t i = 0; i < functions.size(); ++i) {
      const auto& f = functions[i];
      if ((f.function_type == 0 || f.function_type == uff::kTimeResponse) && !f.complex_ordinate &&
          f.x.size() == 0 && f.dx > 0) {
        ++time_records;
      } else if (f.function_type == uff::kFrf && f.complex_ordinate) {
        frf_records.push_back(static_cast<int>(i));
      }
    }
    if (time_records == 0 && !frf_records.empty()) {
      const int n = static_cast<int>(frf_records.size());
      for (int k = 0; k < n; ++k) {
        const auto& f = functions[static_cast<std::size_t>(frf_records[k])];
        std::string ord = frf_ordinate(f.y_unit + "/" + (f.z_unit.empty() ? "N" : f.z_unit));
        if (ord.empty()) ord = frf_ordinate(f.y_label);
        const int d = std::abs(f.response_direction);
        const std::string axis = d == 1 ? "x" : d == 2 ? "y" : "";
        frf_unit(ord, "the record's units '" + f.y_unit + "' per '" + f.z_unit + "'", axis,
                 "the record's response direction " + std::to_string(f.response_direction),
                 "UFF58 FRF record '" + f.id1 + "'", k + 1, n);
      }
      return units;
    }
    if (time_records == 0) {
      std::string held;
      for (std::size_t i = 0; i < functions.size() && i < 4; ++i) {
        held += (i ? ", " : "") + std::string("#") + std::to_string(i + 1) + " '" +
                functions[i].id1 + "' (function type " +
                std::to_string(functions[i].function_type) + ")";
      }
      why_not = "no dataset 58 time record or FRF in the file" +
                (held.empty() ? std::string() : " (it holds " + held + ")");
      return units;
    }
    if (!open_table()) return units;
    const double hz = look.table->file_sample_rate_hz();
    if (hz > 0) {
      look.rate.hz = std::abs(hz - std::round(hz)) < 1e-5 * hz ? std::round(hz) : hz;
      look.rate.why = "from the records' abscissa step dx (" + sig(1.0 / hz, 6) + " s)";
    }
    // The response direction of the time records, when they agree on x or y.
    std::set<int> dirs;
    for (const auto& f : functions) {
      if (f.function_type <= 1 && std::abs(f.response_direction) >= 1 &&
          std::abs(f.response_direction) <= 2) {
        dirs.insert(std::abs(f.response_direction));
      }
    }
    if (dirs.size() == 1) uff_axis = *dirs.begin() == 1 ? "x" : "y";
  } else if (ext == ".mat") {
    if (!open_table()) return units;
    try {
      for (const auto& v : mat::numeric_variables(file)) {
        const std::string n = lower(v.name);
        if ((n == "t" || n == "time") && v.vector() && !v.complex) {
          look.rate =
              rate_from_time(mat::read_vector(file, v.name), 1.0, "the variable '" + v.name + "'");
          if (look.rate.hz > 0) break;
        }
        if (v.scalar() && !v.complex &&
            any_of_words(describe(v.name).compact,
                         {"fs", "samplerate", "samplingrate", "srate", "sr", "fsamp", "fshz",
                          "sampleratehz", "samplingfrequency"})) {
          const double hz = mat::read_matrix(file, v.name)(0, 0);
          if (hz > 0) {
            look.rate = {hz, "from the variable '" + v.name + "'", ""};
            break;
          }
        }
        if (v.scalar() && !v.complex && any_of_words(lower(v.name), {"dt", "ts"})) {
          const double dt = mat::read_matrix(file, v.name)(0, 0);
          if (dt > 0) {
            look.rate = {1.0 / dt, "from the variable '" + v.name + "' (the step, s)", ""};
            break;
          }
        }
      }
    } catch (const InputError&) {
    }
    if (look.rate.hz == 0 && look.rate.todo.empty()) {
      look.rate.todo = "no variable t, time or fs in the file";
    }
  } else {
    return units;
  }

  const TestGuess g = guess_test(look, path_words, uff_axis);
  Unit u;
  u.file = file;
  u.kind = g.kind;
  u.finding = g.kind.empty() ? "kind not decided (channels: " + quoted_list(look.names) + ")"
                             : g.kind + " test (" + g.kind_why + ")";
  const Rate rate = look.rate;
  const DataSpec data = look.data;
  u.render = [g, rate, data](const std::string& ref) {
    YamlText y;
    if (!g.kind.empty()) {
      y.line("kind: " + g.kind, "guessed: " + g.kind_why);
    } else {
      y.todo(g.kind_todo);
    }
    for (const auto& [text, why] : g.keys) {
      if (text.rfind("axis:", 0) == 0 || text.rfind("response:", 0) == 0) y.line(text, why);
    }
    for (const auto& t : g.todos) {
      if (t.rfind("axis:", 0) == 0 || t.rfind("response:", 0) == 0) y.todo(t);
    }
    if (rate.hz > 0) {
      y.line("sample_rate_hz: " + number(rate.hz), rate.why);
    } else {
      y.todo("sample_rate_hz: the sample rate, Hz (" + rate.todo + ")");
    }
    for (const auto& [text, why] : g.keys) {
      if (text.rfind("axis:", 0) != 0 && text.rfind("response:", 0) != 0) y.line(text, why);
    }
    for (const auto& t : g.todos) {
      if (t.rfind("axis:", 0) != 0 && t.rfind("response:", 0) != 0) y.todo(t);
    }
    std::string d = "data: {file: " + yaml_plain_or_quoted(ref);
    std::string dwhy;
    if (data.delimiter != 0 && data.delimiter != ',') {
      d += std::string(", delimiter: ") + (data.delimiter == '\t' ? "tab" : "\";\"");
    }
    if (data.decimal == ',') d += ", decimal: \",\"";
    if (data.skip_lines > 0) d += ", skip_lines: " + std::to_string(data.skip_lines);
    if (d.find(", ") != std::string::npos) dwhy = "the file's dialect, as the reader detects it";
    y.line(d + "}", dwhy);
    bool header = false;
    for (const auto& m : g.channels) {
      const bool needs_column = !m.column.empty() && m.column != m.channel;
      if (!needs_column && m.scale == 1.0) {
        if (!m.todo.empty()) {
          y.todo(m.todo);
        } else if (!m.column.empty()) {
          y.comment("channel " + m.channel + ": the column '" + m.column + "' (named like it)");
        }
        continue;
      }
      if (!header) {
        y.line("channels:");
        header = true;
      }
      std::string entry = "  " + m.channel + ": {";
      if (needs_column) entry += "column: " + yaml_quoted(m.column);
      if (m.scale != 1.0)
        entry += std::string(needs_column ? ", " : "") + "scale: " + number(m.scale);
      y.line(entry + "}", m.why);
      if (!m.todo.empty()) y.todo(m.todo);
    }
    return y.str();
  };
  units.push_back(std::move(u));
  return units;
}

}  // namespace

InitProposal propose_campaign(const fs::path& folder_in) {
  InitProposal p;
  std::error_code ec;
  if (!fs::is_directory(folder_in, ec)) {
    throw InputError(folder_in.string() + ": " +
                     (fs::exists(folder_in, ec) ? "not a folder" : "no such folder"));
  }
  const fs::path root = fs::absolute(folder_in).lexically_normal();
  p.folder = folder_in;

  // Every data file and every test.yaml, by folder.
  std::map<fs::path, std::vector<fs::path>> files_by_dir;
  std::vector<fs::path> yamls;
  const bool has_truth = fs::is_regular_file(root / "truth.yaml", ec);
  for (fs::recursive_directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& path = it->path();
    const std::string name = path.filename().string();
    const auto st = it->symlink_status(ec);
    if (fs::is_directory(st)) {
      if (name.rfind('.', 0) == 0 || is_chatterlab_results(path / "results.json") ||
          (has_truth && path.parent_path() == root && name == "truth")) {
        it.disable_recursion_pending();
      }
      continue;
    }
    if (name.rfind('.', 0) == 0 || !fs::is_regular_file(st)) continue;
    if (name == "test.yaml") {
      yamls.push_back(path);
    } else if (is_data_file(path)) {
      files_by_dir[path.parent_path()].push_back(path);
    }
  }
  const std::set<fs::path> described = described_files(root, yamls);

  struct Planned {
    fs::path dir;
    std::string content;
    std::string kind;
  };
  std::vector<Planned> planned;
  std::set<fs::path> taken;                                   // test folders planned
  std::vector<std::pair<std::string, std::string>> findings;  // by file, in file order
  for (auto& [dir, files] : files_by_dir) {
    std::sort(files.begin(), files.end());
    std::vector<std::pair<fs::path, std::vector<Unit>>> looked;
    for (const auto& f : files) {
      ++p.data_files;
      const std::string label = rel(f, root);
      if (described.count(f.lexically_normal()) > 0) {
        findings.emplace_back(label, "already named by a test.yaml or truth.yaml; left as it is");
        continue;
      }
      std::string why_not;
      auto units = look_at(f, root, why_not);
      if (units.empty()) {
        if (!why_not.empty()) findings.emplace_back(label, "no test proposed: " + why_not);
        continue;
      }
      looked.emplace_back(f, std::move(units));
    }
    // The folder itself is the test when it is not the campaign root and holds this one data
    // file for one test and no test.yaml; otherwise each test gets a folder of its own here.
    const bool own_folder = dir != root && looked.size() == 1 && looked[0].second.size() == 1 &&
                            !fs::exists(dir / "test.yaml", ec) && files.size() == 1;
    std::map<std::string, int> stems;
    for (const auto& [f, units] : looked) ++stems[safe_name(f.stem().string())];
    for (auto& [f, units] : looked) {
      for (auto& u : units) {
        fs::path test_dir = dir;
        std::string ref = f.filename().string();
        if (!own_folder) {
          std::string name = safe_name(f.stem().string());
          if (stems[name] > 1) name += "-" + lower(f.extension().string().substr(1));
          name += u.suffix;
          while (taken.count(dir / name) > 0 ||
                 (fs::exists(fs::symlink_status(dir / name, ec)) &&
                  !fs::is_directory(fs::symlink_status(dir / name, ec)))) {
            name += "-test";
          }
          test_dir = dir / name;
          ref = "../" + ref;
        }
        taken.insert(test_dir);
        const std::string id = rel(test_dir, root);
        findings.emplace_back(rel(f, root), u.finding + " -> " + id + "/test.yaml");
        planned.push_back({test_dir,
                           "# proposed by chatterlab init from " + rel(f, root) +
                               ": check every line; each TODO names a key still to set\n" +
                               u.render(ref),
                           u.kind});
      }
    }
  }

  std::stable_sort(findings.begin(), findings.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [label, text] : findings) p.findings.push_back(label + ": " + text);

  // campaign.yaml: format and name; the tool when a kind needs it.
  const bool needs_tool = std::any_of(planned.begin(), planned.end(), [](const Planned& t) {
    return t.kind == "cut" || t.kind == "dyno-slot" || t.kind == "sifs-cut";
  });
  YamlText c;
  c.comment("proposed by chatterlab init: check every line; each TODO names a key still to set");
  c.line("format: chatterlab-campaign/1");
  std::string name = safe_name(root.filename().string());
  c.line("name: " + name, "the folder's name");
  if (needs_tool) {
    c.todo("tool: {teeth: N, radius_mm: R}: required, the campaign holds cut or dyno-slot tests");
  } else {
    c.comment("tool: {teeth: N, radius_mm: R}: needed only by cut, dyno-slot and sifs-cut tests");
  }
  InitFile campaign{"campaign.yaml", c.str(), fs::exists(root / "campaign.yaml", ec), false};
  p.files.push_back(campaign);
  std::sort(planned.begin(), planned.end(),
            [](const Planned& a, const Planned& b) { return a.dir < b.dir; });
  for (const auto& t : planned) {
    const std::string id = rel(t.dir, root);
    InitFile f;
    f.path = (id.empty() ? "" : id + "/") + "test.yaml";
    f.content = t.content;
    f.exists = fs::exists(t.dir / "test.yaml", ec);
    p.files.push_back(f);
    ++p.tests;
  }
  return p;
}

void write_proposal(InitProposal& proposal) {
  const fs::path root = proposal.folder;
  for (auto& f : proposal.files) {
    const fs::path path = root / f.path;
    std::error_code ec;
    if (f.exists || fs::exists(path, ec)) {
      f.exists = true;
      continue;
    }
    // Only inside the folder: a test folder reached through a link that leads out is refused.
    const fs::path real_root = fs::weakly_canonical(fs::absolute(root), ec);
    const fs::path real_parent = fs::weakly_canonical(fs::absolute(path.parent_path()), ec);
    const fs::path inside = real_parent.lexically_relative(real_root);
    if (ec || inside.empty() || *inside.begin() == "..") {
      throw InputError(f.path + ": its folder leads out of " + root.string() +
                       " (a linked folder): not written");
    }
    fs::create_directories(path.parent_path(), ec);
    std::ofstream out = open_for_writing(path);
    out << f.content;
    close_checked(out, path);
    f.written = true;
  }
}

int run_init(const fs::path& folder, bool write, std::ostream& out) {
  InitProposal p = propose_campaign(folder);
  out << "init: " << folder.string() << ": " << p.data_files << " data file"
      << (p.data_files == 1 ? "" : "s") << ", " << p.tests << " test" << (p.tests == 1 ? "" : "s")
      << " proposed\n";
  for (const auto& f : p.findings) out << "  " << f << "\n";
  if (p.data_files == 0) {
    out << "init: no data file (.csv, .txt, .tsv, .lvm, .uff, .unv, .mat, FRF tables) below "
        << folder.string() << "; nothing proposed\n";
    return kExitInputError;
  }
  if (write) write_proposal(p);
  for (const auto& f : p.files) {
    out << "\n";
    if (f.exists) {
      out << "=== " << f.path << ": exists, kept as it is (init never overwrites it)\n";
      continue;
    }
    out << "=== " << f.path << (f.written ? " (written)" : " (new)") << "\n" << f.content;
  }
  out << "\n";
  std::vector<std::string> written, kept, would;
  for (const auto& f : p.files) {
    (f.exists ? kept : f.written ? written : would).push_back(f.path);
  }
  const auto list = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  };
  if (write) {
    out << "init: wrote " << written.size() << " file" << (written.size() == 1 ? "" : "s")
        << (written.empty() ? "" : ": " + list(written)) << "\n";
  } else {
    out << "init: nothing written; run again with --write to write " << would.size() << " file"
        << (would.size() == 1 ? "" : "s") << "\n";
  }
  if (!kept.empty()) {
    out << "init: skipped " << list(kept) << " (exist" << (kept.size() == 1 ? "s" : "")
        << ": never overwritten)\n";
  }
  out << "next: set the TODO keys, then run chatterlab validate " << folder.string()
      << " to see what is still missing\n";
  return kExitOk;
}

}  // namespace chatterlab::app

// The `era` section of a synth spec (docs/format/synth-spec.md): frf tests <folder>/<name> of
// random stable discrete systems (analysis/sysid/random_system.h), each the FFT of its impulse
// response with white noise at a stated SNR, as 001 sec. 3.3 validates ERA; truth as format
// section 5 (order, snr_db, noise_std, the noise-free FRF, the modes with their peak-to-noise
// ratio).
#include <cmath>
#include <random>

#include "analysis/signal/fft.h"
#include "analysis/sysid/random_system.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/sysid/sysid_kinds.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

namespace {

struct EraSystemSpec {
  std::string name;
  int order = 10;
  double snr_db = 10.0;  // +inf (.inf) : no noise
};

struct EraSynthSpec : KindSpec {
  std::string folder = "era";
  double fs_hz = 10000.0;
  int record_samples = 2048;
  std::vector<EraSystemSpec> systems;
};

bool is_name(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) {
      return false;
    }
  }
  return true;
}

}  // namespace

std::shared_ptr<const KindSpec> FrfKind::parse_synth(const YAML::Node& section, const SynthContext&,
                                                     YamlReader& r) const {
  auto s = std::make_shared<EraSynthSpec>();
  if (!section.IsMap()) {
    r.error("era", "must be a mapping with a list `systems` (docs/format/synth-spec.md)");
    return s;
  }
  r.check_keys(section, {"folder", "sample_rate_hz", "record_samples", "systems"}, "era");
  s->folder = r.optional_string(section, "folder", "era").value_or(s->folder);
  if (!is_name(s->folder)) r.error("era.folder", "must be a folder name such as era");
  if (const auto v = r.optional_double(section, "sample_rate_hz", "era")) s->fs_hz = *v;
  if (!(s->fs_hz > 0.0)) r.error("era.sample_rate_hz", "must be > 0");
  if (const auto n = r.optional_int(section, "record_samples", "era", 64, 1 << 20)) {
    if (*n % 2 != 0) r.error("era.record_samples", "must be even");
    s->record_samples = static_cast<int>(*n);
  }
  const YAML::Node list = section["systems"];
  if (!list || !list.IsSequence() || list.size() == 0) {
    r.error("era.systems", "is required: a list of {name, order, snr_db}");
    return s;
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string p = "era.systems[" + std::to_string(i) + "]";
    const YAML::Node e = list[i];
    if (!e.IsMap()) {
      r.error(p, "must be {name, order, snr_db}");
      continue;
    }
    r.check_keys(e, {"name", "order", "snr_db"}, p);
    EraSystemSpec sys;
    sys.name = r.required_string(e, "name", p);
    if (!sys.name.empty() && !is_name(sys.name)) r.error(p + ".name", "must be [A-Za-z0-9._-]+");
    if (const auto n = r.required_int(e, "order", p, 1, 200)) sys.order = static_cast<int>(*n);
    if (e["snr_db"]) {
      double v = 0.0;
      if (!e["snr_db"].IsScalar() || !YAML::convert<double>::decode(e["snr_db"], v) ||
          std::isnan(v) || v == -std::numeric_limits<double>::infinity()) {
        r.error(p + ".snr_db", "must be a number (dB) or .inf for no noise");
      } else {
        sys.snr_db = v;
      }
    }
    s->systems.push_back(sys);
  }
  return s;
}

int FrfKind::write_synth(const KindSpec& section, SynthContext& ctx) const {
  const auto& s = dynamic_cast<const EraSynthSpec&>(section);
  const int N = s.record_samples;
  const double fs = s.fs_hz;
  signal::RealFft fft(N);
  int written = 0;
  for (std::size_t i = 0; i < s.systems.size(); ++i) {
    const EraSystemSpec& sys = s.systems[i];
    sysid::RandomSystemOptions o;
    o.order = sys.order;
    const sysid::DiscreteStateSpace truth =
        sysid::random_stable_system(o, fs, ctx.stream_seed("synth.era.system", i));
    // Impulse response (001 eq. 3.12), white noise at the SNR over the record.
    Eigen::VectorXd y(N);
    y[0] = truth.D;
    Eigen::VectorXd x = truth.B;
    for (int k = 1; k < N; ++k) {
      y[k] = (truth.C * x)(0);
      x = truth.A * x;
    }
    const double power = y.squaredNorm() / N;
    const double sigma =
        std::isinf(sys.snr_db) ? 0.0 : std::sqrt(power / std::pow(10.0, sys.snr_db / 10.0));
    std::mt19937_64 rng(ctx.stream_seed("synth.era.noise", i));
    std::normal_distribution<double> nd(0.0, 1.0);
    for (int k = 0; k < N; ++k) y[k] += sigma * nd(rng);
    const Eigen::VectorXcd G = fft.forward(y);
    const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(N / 2 + 1, 0.0, 0.5 * fs);
    const Eigen::VectorXd re = G.real(), im = G.imag();
    const std::string id = s.folder + "/" + sys.name;
    const auto dir = ctx.out / id;
    std::filesystem::create_directories(dir);
    write_signals(dir / "frf.csv", {"freq_hz", "re", "im"}, {&f, &re, &im});
    YAML::Emitter e;
    configure_synth_emitter(e);
    e << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "frf";
    e << YAML::Key << "sample_rate_hz" << YAML::Value << fs;
    e << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
      << YAML::Value << "frf.csv" << YAML::EndMap;
    e << YAML::Key << "input_unit" << YAML::Value << "N*m";
    e << YAML::Key << "output_unit" << YAML::Value << "A";
    e << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", e);
    // Truth: the noise-free FRF on the same grid, the modes and their peak over the noise.
    const Eigen::VectorXcd G0 = sysid::frequency_response(truth, f);
    const Eigen::VectorXd re0 = G0.real(), im0 = G0.imag();
    const std::string truth_csv = "truth/" + underscored(id) + ".csv";
    std::filesystem::create_directories((ctx.out / truth_csv).parent_path());
    write_signals(ctx.out / truth_csv, {"freq_hz", "re", "im"}, {&f, &re0, &im0});
    YAML::Node t(YAML::NodeType::Map);
    t["order"] = sys.order;
    t["snr_db"] = std::isinf(sys.snr_db) ? std::string(".inf") : synth_number(sys.snr_db);
    t["sample_rate_hz"] = synth_number(fs);
    t["noise_std"] = synth_number(sigma);
    t["frf_file"] = truth_csv;
    YAML::Node modes(YAML::NodeType::Sequence);
    const double noise_bin = sigma * std::sqrt(static_cast<double>(N));  // FFT of white noise
    for (const auto& md : sysid::modes_of(sysid::poles(truth), fs)) {
      YAML::Node m(YAML::NodeType::Map);
      m["fn_hz"] = synth_number(md.fn_hz);
      m["zeta"] = synth_number(md.zeta);
      if (noise_bin > 0.0 && md.fn_hz < 0.5 * fs) {
        Eigen::VectorXd fn(1);
        fn << md.fn_hz;
        m["peak_to_noise"] =
            synth_number(std::abs(sysid::frequency_response(truth, fn)[0]) / noise_bin);
      }
      m.SetStyle(YAML::EmitterStyle::Flow);
      modes.push_back(m);
    }
    t["modes"] = modes;
    ctx.truth.tests[id] = t;
    ++written;
  }
  return written;
}

}  // namespace chatterlab::app

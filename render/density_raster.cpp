#include "render/density_raster.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>

#include "render/osmesa_context.h"
#include "render/render_error.h"

namespace chatterlab::render {
namespace {

constexpr int kMaxSidePx = 16384;
// Points staged and dispatched at a time: 8 MB of floats, 4096 work groups of 256.
constexpr std::size_t kChunkPoints = std::size_t{1} << 20;
constexpr unsigned kGroupSize = 256;
// Staged value of a point that must not be counted: below every range's low end (linear
// ranges start at 0 after the shift, log ranges at a positive value). GLSL does not promise
// IEEE comparisons with NaN, so NaN never reaches the shader.
constexpr float kRejected = -std::numeric_limits<float>::max();

// One thread of the compute shader per point: range check, pixel coordinates (log2 on log
// axes, where the CPU has left the value unshifted; y counted from the bottom), then one
// atomic add of weight `unit` (whole points), or four bilinear weights of 1/16 x 1/16 steps
// summing to 256 (antialias) to the pixels whose centres surround the point.
constexpr const char* kCountShader = R"(#version 430 core
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Points { vec2 points[]; };
layout(std430, binding = 1) buffer Counts { uint counts[]; };
uniform uint n;
uniform vec2 lo;
uniform vec2 hi;
uniform vec2 origin;
uniform vec2 scale;
uniform ivec2 logscale;
uniform ivec2 size;
uniform int antialias;
void add(ivec2 k, uint w) {
  if (w != 0u) atomicAdd(counts[(size.y - 1 - k.y) * size.x + k.x], w);
}
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= n) return;
  vec2 p = points[i];
  if (p.x < lo.x || p.y < lo.y || p.x > hi.x || p.y > hi.y) return;
  vec2 a = vec2(logscale.x != 0 ? log2(p.x) : p.x, logscale.y != 0 ? log2(p.y) : p.y);
  vec2 q = (a - origin) * scale;
  ivec2 last = size - ivec2(1);
  if (antialias == 0) {
    add(clamp(ivec2(floor(q)), ivec2(0), last), 1u);
    return;
  }
  q -= vec2(0.5);
  vec2 f = floor(q);
  uvec2 w1 = uvec2(round((q - f) * 16.0));
  uvec2 w0 = uvec2(16u) - w1;
  ivec2 c0 = clamp(ivec2(f), ivec2(0), last);
  ivec2 c1 = clamp(ivec2(f) + ivec2(1), ivec2(0), last);
  add(c0, w0.x * w0.y);
  add(ivec2(c1.x, c0.y), w1.x * w0.y);
  add(ivec2(c0.x, c1.y), w0.x * w1.y);
  add(c1, w1.x * w1.y);
}
)";
// Weight of one point in the counts buffer with antialias: 16 x 16 bilinear steps.
constexpr double kAntialiasUnit = 256.0;

// How one axis maps to pixels in the shader.
struct AxisMap {
  double shift = 0.0;  // subtracted on the CPU in double (linear axes: the range's start)
  float lo = 0.0f;     // inclusive range of staged values
  float hi = 0.0f;
  float origin = 0.0f;  // subtracted in the shader after log2 (log axes: log2 of the start)
  float scale = 0.0f;   // pixels per staged (or log2) unit
  bool log = false;
};

AxisMap axis_map(const Range& r, bool log, int pixels) {
  AxisMap m;
  m.log = log;
  if (log) {
    m.lo = static_cast<float>(r.min);
    m.hi = static_cast<float>(r.max);
    m.origin = static_cast<float>(std::log2(r.min));
    m.scale = static_cast<float>(pixels / std::log2(r.max / r.min));
  } else {
    m.shift = r.min;
    m.hi = static_cast<float>(r.max - r.min);
    m.scale = static_cast<float>(pixels / (r.max - r.min));
  }
  return m;
}

template <class T>
float stage(T v, const AxisMap& m) {
  const double shifted = static_cast<double>(v) - m.shift;
  // Also rejects NaN and values beyond float's range.
  return shifted >= -1e30 && shifted <= 1e30 ? static_cast<float>(shifted) : kRejected;
}

void check_range(const char* name, const Range& r, bool log) {
  if (!std::isfinite(r.min) || !std::isfinite(r.max) || !(r.max > r.min)) {
    throw RenderError(std::string("count_density: ") + name + " = [" + message_number(r.min) +
                      ", " + message_number(r.max) + "]: must be finite with max > min");
  }
  if (log && !(r.min > 0.0)) {
    throw RenderError(std::string("count_density: ") + name + " = [" + message_number(r.min) +
                      ", " + message_number(r.max) + "]: must be > 0 on a log axis");
  }
}

void check_side(const char* name, int px) {
  if (px < 1 || px > kMaxSidePx) {
    throw RenderError(std::string("count_density: ") + name + " = " + std::to_string(px) +
                      ": must be in [1, " + std::to_string(kMaxSidePx) + "]");
  }
}

GLuint compile_count_program() {
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  glShaderSource(shader, 1, &kCountShader, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  std::array<char, 2000> log{};
  if (ok != GL_TRUE) {
    glGetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), nullptr, log.data());
    throw RenderError(std::string("density rasterizer: compute shader does not compile: ") +
                      log.data());
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, shader);
  glLinkProgram(program);
  glDeleteShader(shader);
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    glGetProgramInfoLog(program, static_cast<GLsizei>(log.size()), nullptr, log.data());
    throw RenderError(std::string("density rasterizer: compute shader does not link: ") +
                      log.data());
  }
  return program;
}

// The calling thread's GL context with the counting program and its buffers. The GL names
// die with the context, which the destructor destroys.
class DensityKernel {
 public:
  DensityKernel() : context_(4, 3), program_(compile_count_program()) {
    glGenBuffers(1, &points_);
    glGenBuffers(1, &counts_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, points_);
    glBufferData(GL_SHADER_STORAGE_BUFFER,
                 static_cast<GLsizeiptr>(kChunkPoints * 2 * sizeof(float)), nullptr,
                 GL_STREAM_DRAW);
    staging_.resize(2 * kChunkPoints);
    check_gl("setup");
  }

  void make_current() { context_.make_current(); }
  std::string description() { return context_.description(); }

  template <class T>
  void count(const std::vector<T>& x, const std::vector<T>& y, const AxisMap& mx, const AxisMap& my,
             bool antialias, DensityGrid& grid) {
    const std::size_t pixels =
        static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height);
    glUseProgram(program_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, counts_);
    if (pixels > counts_capacity_) {
      glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(pixels * sizeof(GLuint)),
                   nullptr, GL_DYNAMIC_READ);
      counts_capacity_ = pixels;
    }
    const GLuint zero = 0;
    glClearBufferSubData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, 0,
                         static_cast<GLsizeiptr>(pixels * sizeof(GLuint)), GL_RED_INTEGER,
                         GL_UNSIGNED_INT, &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, points_);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, counts_);
    glUniform2f(uniform("lo"), mx.lo, my.lo);
    glUniform2f(uniform("hi"), mx.hi, my.hi);
    glUniform2f(uniform("origin"), mx.origin, my.origin);
    glUniform2f(uniform("scale"), mx.scale, my.scale);
    glUniform2i(uniform("logscale"), mx.log ? 1 : 0, my.log ? 1 : 0);
    glUniform2i(uniform("size"), grid.width, grid.height);
    glUniform1i(uniform("antialias"), antialias ? 1 : 0);
    const GLint n_location = uniform("n");

    glBindBuffer(GL_SHADER_STORAGE_BUFFER, points_);
    for (std::size_t start = 0; start < x.size(); start += kChunkPoints) {
      const std::size_t n = std::min(kChunkPoints, x.size() - start);
      float* out = staging_.data();
      for (std::size_t i = start; i < start + n; ++i) {
        *out++ = stage(x[i], mx);
        *out++ = stage(y[i], my);
      }
      glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(n * 2 * sizeof(float)),
                      staging_.data());
      glUniform1ui(n_location, static_cast<GLuint>(n));
      glDispatchCompute(static_cast<GLuint>((n + kGroupSize - 1) / kGroupSize), 1, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, counts_);
    units_.resize(pixels);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0,
                       static_cast<GLsizeiptr>(pixels * sizeof(GLuint)), units_.data());
    check_gl("counting");
    const double per_point = antialias ? kAntialiasUnit : 1.0;
    for (std::size_t i = 0; i < pixels; ++i) {
      grid.counts[i] = static_cast<float>(units_[i] / per_point);
    }
  }

 private:
  GLint uniform(const char* name) const { return glGetUniformLocation(program_, name); }

  static void check_gl(const char* step) {
    const GLenum error = glGetError();
    if (error != GL_NO_ERROR) {
      std::array<char, 16> hex{};
      std::snprintf(hex.data(), hex.size(), "0x%04x", error);
      throw RenderError(std::string("density rasterizer: OpenGL error ") + hex.data() + " in " +
                        step);
    }
  }

  OsmesaContext context_;
  GLuint program_ = 0;
  GLuint points_ = 0;
  GLuint counts_ = 0;
  std::size_t counts_capacity_ = 0;
  std::vector<float> staging_;
  std::vector<GLuint> units_;
};

DensityKernel& kernel_for_this_thread() {
  // One per thread (a context is current in one thread at a time), created on first use:
  // ~15 ms for the context and the shader's JIT compile, then reused by every figure.
  thread_local std::unique_ptr<DensityKernel> kernel;
  if (!kernel) kernel = std::make_unique<DensityKernel>();
  kernel->make_current();
  return *kernel;
}

template <class T>
DensityGrid count_impl(const std::vector<T>& x, const std::vector<T>& y, const Range& x_range,
                       const Range& y_range, int width_px, int height_px,
                       const DensityOptions& options) {
  if (x.size() != y.size()) {
    throw RenderError("count_density: x has " + std::to_string(x.size()) + " values, y has " +
                      std::to_string(y.size()) + ": must be equal");
  }
  check_side("width_px", width_px);
  check_side("height_px", height_px);
  check_range("x_range", x_range, options.log_x);
  check_range("y_range", y_range, options.log_y);
  DensityGrid grid;
  grid.width = width_px;
  grid.height = height_px;
  grid.counts.assign(static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px),
                     0.0f);
  if (x.empty()) return grid;
  kernel_for_this_thread().count(x, y, axis_map(x_range, options.log_x, width_px),
                                 axis_map(y_range, options.log_y, height_px),
                                 options.style.antialias, grid);
  return grid;
}

struct Rgb {
  std::uint8_t r, g, b;
};

Rgb parse_colour(const std::string& c) {
  const auto hex = [](char h) -> int {
    if (h >= '0' && h <= '9') return h - '0';
    if (h >= 'a' && h <= 'f') return h - 'a' + 10;
    if (h >= 'A' && h <= 'F') return h - 'A' + 10;
    return -1;
  };
  bool ok = c.size() == 7 && c[0] == '#';
  std::array<int, 3> v{};
  for (std::size_t i = 0; ok && i < 3; ++i) {
    const int hi = hex(c[1 + 2 * i]), lo = hex(c[2 + 2 * i]);
    ok = hi >= 0 && lo >= 0;
    v[i] = 16 * hi + lo;
  }
  if (!ok) throw RenderError("shade_density: colour = '" + c + "': must be #RRGGBB");
  return {static_cast<std::uint8_t>(v[0]), static_cast<std::uint8_t>(v[1]),
          static_cast<std::uint8_t>(v[2])};
}

// t in [0, 1] for a count n >= 1 (see shade_density).
double density_fraction(double n, double full, DensityScale scale) {
  if (!(full > 1.0)) return 1.0;
  double t = 1.0;
  switch (scale) {
    case DensityScale::kLog:
      t = std::log(n) / std::log(full);
      break;
    case DensityScale::kSqrt:
      t = (std::sqrt(n) - 1.0) / (std::sqrt(full) - 1.0);
      break;
    case DensityScale::kLinear:
      t = (n - 1.0) / (full - 1.0);
      break;
    case DensityScale::kEqualized:  // handled by shade_density
      break;
  }
  return std::clamp(t, 0.0, 1.0);
}

}  // namespace

double DensityGrid::total() const {
  double sum = 0.0;
  for (const float c : counts) sum += static_cast<double>(c);
  return sum;
}

float DensityGrid::max_count() const {
  return counts.empty() ? 0.0f : *std::max_element(counts.begin(), counts.end());
}

DensityGrid count_density(const std::vector<double>& x, const std::vector<double>& y,
                          const Range& x_range, const Range& y_range, int width_px, int height_px,
                          const DensityOptions& options) {
  return count_impl(x, y, x_range, y_range, width_px, height_px, options);
}

DensityGrid count_density(const std::vector<float>& x, const std::vector<float>& y,
                          const Range& x_range, const Range& y_range, int width_px, int height_px,
                          const DensityOptions& options) {
  return count_impl(x, y, x_range, y_range, width_px, height_px, options);
}

RgbaImage shade_density(const DensityGrid& grid, const std::string& hex_colour,
                        const DensityStyle& style) {
  const Rgb colour = parse_colour(hex_colour);
  if (!(style.min_alpha > 0.0 && style.min_alpha <= 1.0 && style.max_alpha >= style.min_alpha &&
        style.max_alpha <= 1.0 && style.full_count >= 0.0)) {
    throw RenderError("shade_density: alphas [" + message_number(style.min_alpha) + ", " +
                      message_number(style.max_alpha) + "], full_count " +
                      message_number(style.full_count) +
                      ": need 0 < min_alpha <= max_alpha <= 1 and full_count >= 0");
  }
  const double full =
      style.full_count > 0.0 ? style.full_count : static_cast<double>(grid.max_count());
  // kEqualized: t(n) = share of non-empty pixels holding less than n, over that share for
  // the full count, so that the least count gets min_alpha and the full count max_alpha.
  std::vector<float> sorted;
  if (style.scale == DensityScale::kEqualized) {
    for (const float n : grid.counts) {
      if (n >= 1.0f) sorted.push_back(n);
    }
    std::sort(sorted.begin(), sorted.end());
  }
  const auto fewer_than = [&](double n) {
    return static_cast<double>(
        std::lower_bound(sorted.begin(), sorted.end(), static_cast<float>(n)) - sorted.begin());
  };
  const double fewer_than_full = style.scale == DensityScale::kEqualized ? fewer_than(full) : 0;
  const auto alpha_of = [&](double n) {
    if (n < 1.0) return style.min_alpha * n;
    double t = 1.0;
    if (style.scale != DensityScale::kEqualized) {
      t = density_fraction(n, full, style.scale);
    } else if (fewer_than_full > 0.0) {
      t = std::min(1.0, fewer_than(n) / fewer_than_full);
    }
    return style.min_alpha + (style.max_alpha - style.min_alpha) * t;
  };
  RgbaImage image;
  image.width = grid.width;
  image.height = grid.height;
  image.rgba.assign(4 * grid.counts.size(), 0);
  for (std::size_t i = 0; i < grid.counts.size(); ++i) {
    const float n = grid.counts[i];
    if (!(n > 0.0f)) continue;
    std::uint8_t* p = image.rgba.data() + 4 * i;
    p[0] = colour.r;
    p[1] = colour.g;
    p[2] = colour.b;
    p[3] = static_cast<std::uint8_t>(std::lround(255.0 * alpha_of(static_cast<double>(n))));
  }
  return image;
}

RgbaImage rasterize_density(const std::vector<double>& x, const std::vector<double>& y,
                            const Range& x_range, const Range& y_range, int width_px, int height_px,
                            const DensityOptions& options) {
  return shade_density(count_density(x, y, x_range, y_range, width_px, height_px, options),
                       options.color, options.style);
}

RgbaImage rasterize_density(const std::vector<float>& x, const std::vector<float>& y,
                            const Range& x_range, const Range& y_range, int width_px, int height_px,
                            const DensityOptions& options) {
  return shade_density(count_density(x, y, x_range, y_range, width_px, height_px, options),
                       options.color, options.style);
}

std::string density_renderer() { return kernel_for_this_thread().description(); }

}  // namespace chatterlab::render

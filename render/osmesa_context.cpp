#include "render/osmesa_context.h"

#include <GL/osmesa.h>

#include <mutex>

#include "render/render_error.h"

namespace chatterlab::render {
namespace {

OSMesaContext as_context(void* c) { return static_cast<OSMesaContext>(c); }

std::string gl_string(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? reinterpret_cast<const char*>(s) : "?";
}

}  // namespace

OsmesaContext::OsmesaContext(int major, int minor) {
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            major,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            minor,
                            0};
  {
    // Mesa creates its screen once per process; creation is serialised here so that two
    // report threads asking at once do not rely on Mesa's own locking.
    static std::mutex creation;
    const std::lock_guard<std::mutex> lock(creation);
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
  }
  if (!context_) {
    throw RenderError("OSMesa cannot create an OpenGL " + std::to_string(major) + "." +
                      std::to_string(minor) +
                      " core context (needed by the density rasterizer; Mesa's llvmpipe "
                      "driver offers 4.5: check that libosmesa6 is installed and that "
                      "GALLIUM_DRIVER, if set, names llvmpipe)");
  }
  make_current();
}

OsmesaContext::~OsmesaContext() {
  if (OSMesaGetCurrentContext() == as_context(context_)) {
    OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
  }
  OSMesaDestroyContext(as_context(context_));
}

void OsmesaContext::make_current() {
  if (OSMesaGetCurrentContext() == as_context(context_)) return;
  if (!OSMesaMakeCurrent(as_context(context_), pixel_.data(), GL_UNSIGNED_BYTE, 1, 1)) {
    throw RenderError("OSMesa cannot make its OpenGL context current");
  }
}

std::string OsmesaContext::description() {
  make_current();
  return gl_string(GL_RENDERER) + ", OpenGL " + gl_string(GL_VERSION);
}

}  // namespace chatterlab::render

#if defined(__SANITIZE_ADDRESS__)
// Mesa keeps a few hundred bytes per process (its screen, framebuffer records made by
// OSMesaMakeCurrent) that it never frees; LeakSanitizer would fail every sanitizer run
// (CHATTERLAB_SANITIZE) of a program that rasterized. The hook is LeakSanitizer's documented
// default-suppressions entry point; it lives here so that every such program links it.
extern "C" const char* __lsan_default_suppressions() { return "leak:libOSMesa.so\n"; }
#endif

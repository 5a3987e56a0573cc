// An off-screen OpenGL context through OSMesa (Mesa's llvmpipe, software, no display):
// the render layer's GPU for dense scatter now and 3-D views later. A context is current
// in one thread at a time, so users keep one per thread (density_raster.cpp does).
#pragma once

#include <array>
#include <string>

namespace chatterlab::render {

class OsmesaContext {
 public:
  // A core-profile context of at least OpenGL major.minor. Throws RenderError when OSMesa
  // cannot create one (e.g. GALLIUM_DRIVER=softpipe offers only 3.3, no compute shaders).
  OsmesaContext(int major, int minor);
  OsmesaContext(const OsmesaContext&) = delete;
  OsmesaContext& operator=(const OsmesaContext&) = delete;
  ~OsmesaContext();

  // Binds the context to the calling thread (a no-op when it already is). Drawing goes to
  // framebuffer objects or buffers the user creates; the default framebuffer is 1 x 1.
  void make_current();

  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core
  // Profile) Mesa 22.3.6", for logs and benchmark labels.
  std::string description();

 private:
  void* context_ = nullptr;  // OSMesaContext, kept opaque so that GL headers stay private
  std::array<unsigned char, 4> pixel_{};
};

}  // namespace chatterlab::render

#include "sim/gl_context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

namespace scancrew::sim {

struct GlContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

Result<std::unique_ptr<GlContext>, std::string> GlContext::create() {
  auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_display == nullptr)
    return make_unexpected(std::string("no GL available: EGL lacks eglGetPlatformDisplayEXT"));
  // surfaceless Mesa: plain eglGetDisplay(EGL_DEFAULT_DISPLAY) needs an X server
  EGLDisplay display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || eglInitialize(display, &major, &minor) != EGL_TRUE)
    return make_unexpected(
        std::string("no GL available: cannot initialise the EGL surfaceless display "
                    "(install libegl-mesa0 and libgl1-mesa-dri)"));
  // surfaceless displays offer pbuffer configs only (the default asks for windows)
  const EGLint attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                               EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  if (eglChooseConfig(display, attributes, &config, 1, &count) != EGL_TRUE || count < 1) {
    eglTerminate(display);
    return make_unexpected(std::string("no GL available: no EGL config renders desktop OpenGL"));
  }
  eglBindAPI(EGL_OPENGL_API);
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
  if (context == EGL_NO_CONTEXT) {
    eglTerminate(display);
    return make_unexpected(std::string("no GL available: eglCreateContext failed"));
  }
  auto gl = std::unique_ptr<GlContext>(new GlContext());
  gl->impl_ = std::make_unique<Impl>();
  gl->impl_->display = display;
  gl->impl_->context = context;
  gl->make_current();
  return gl;
}

GlContext::~GlContext() {
  if (!impl_) return;
  eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(impl_->display, impl_->context);
  eglTerminate(impl_->display);
}

void GlContext::make_current() {
  if (eglGetCurrentContext() != impl_->context)
    eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context);
}

void GlContext::release() {
  if (eglGetCurrentContext() == impl_->context)
    eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

}  // namespace scancrew::sim

#pragma once

// GlContext: a headless OpenGL context (EGL, surfaceless Mesa: no GPU or X server needed;
// llvmpipe renders on the CPU). One serves every robot's cameras.
// Thread safety: a context is current in one thread at a time; make_current() moves it
// to the calling thread (cheap when it is already there) once the thread that had it
// called release() (EGL refuses a context current in another thread).

#include <memory>
#include <string>

#include "core/result.hpp"

namespace scancrew::sim {

class GlContext {
 public:
  // Fails with the EGL step that failed (no EGL library, no surfaceless platform, ...).
  static Result<std::unique_ptr<GlContext>, std::string> create();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  void make_current();
  // Not current in this thread any more: another thread may make it current.
  void release();

 private:
  GlContext() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::sim

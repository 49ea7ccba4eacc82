// Times GPU work. Where timer queries are valid it uses GL_TIME_ELAPSED; on llvmpipe, whose
// timer queries report nonsense (docs/gpu.md), it brackets the work with glFinish and a wall clock.
// Every result says which clock measured it.
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include "gl/gl.h"

namespace blurlab {

class Context;

class Timer : NotCopyable {
 public:
  explicit Timer(std::shared_ptr<Context> context);
  ~Timer();

  void start();
  // Ends the interval and returns its length in milliseconds (waits for the GPU).
  double stop();
  // stop() in two steps, so that many intervals can be read after one wait instead of one wait
  // each: end() ends the interval without waiting for a GPU clock's result (the wall clock
  // still waits, glFinish being its measurement); result() waits for it and returns the
  // milliseconds. result() before end() throws std::logic_error.
  void end();
  double result();
  // "gl_time_elapsed" or "wall_glfinish".
  const char* clock() const;

 private:
  std::shared_ptr<Context> context_;
  bool gpu_clock_;
  bool running_ = false;
  bool ended_ = false;
  GLuint query_ = 0;
  std::chrono::steady_clock::time_point start_, end_;
};

}  // namespace blurlab

#include "gl/timer.h"

#include "gl/context.h"

namespace blurlab {

Timer::Timer(std::shared_ptr<Context> context)
    : context_(std::move(context)), gpu_clock_(context_->timer_queries_valid()) {
  if (gpu_clock_) {
    context_->make_current();
    glCreateQueries(GL_TIME_ELAPSED, 1, &query_);
    check_gl("creating a timer query");
    context_->track("query", +1);
  }
}

Timer::~Timer() {
  if (!query_) return;
  // A query still running can only be ended now, on the owner's thread: ended later, the
  // EndQuery would end whichever timer runs then.
  if (running_ && context_->try_make_current()) glEndQuery(GL_TIME_ELAPSED);
  context_->release("query", [query = query_] { glDeleteQueries(1, &query); });
}

const char* Timer::clock() const {
  return gpu_clock_ ? "gl_time_elapsed" : "wall_glfinish";
}

void Timer::start() {
  if (running_) throw std::logic_error("blurlab: Timer.start() called twice without stop()");
  context_->make_current();
  if (gpu_clock_) {
    glBeginQuery(GL_TIME_ELAPSED, query_);
  } else {
    context_->count_wait();
    glFinish();  // earlier work must not be counted
    start_ = std::chrono::steady_clock::now();
  }
  running_ = true;
  ended_ = false;
  check_gl("starting a timer");
}

double Timer::stop() {
  end();
  return result();
}

void Timer::end() {
  if (!running_) throw std::logic_error("blurlab: Timer.stop() called before start()");
  context_->make_current();
  running_ = false;
  ended_ = true;
  if (gpu_clock_) {
    glEndQuery(GL_TIME_ELAPSED);
    check_gl("ending a timer query");
    return;
  }
  context_->count_wait();
  glFinish();
  end_ = std::chrono::steady_clock::now();
}

double Timer::result() {
  if (!ended_) throw std::logic_error("blurlab: Timer.result() called before the timer ended");
  if (gpu_clock_) {
    context_->make_current();
    GLuint64 ns = 0;
    // Reading a result that is already there does not stop the CPU.
    GLuint available = GL_FALSE;
    glGetQueryObjectuiv(query_, GL_QUERY_RESULT_AVAILABLE, &available);
    if (!available) context_->count_wait();
    glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
    check_gl("reading a timer query");
    return static_cast<double>(ns) * 1e-6;
  }
  return std::chrono::duration<double, std::milli>(end_ - start_).count();
}

}  // namespace blurlab

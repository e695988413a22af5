#include "raster/raster_renderer.h"

#include <condition_variable>
#include <deque>
#include <exception>
#include <future>
#include <mutex>
#include <new>
#include <thread>
#include <utility>

#include "raster/render_state.h"
#include "vscan/gl/egl_context.h"

namespace vscan::raster {
namespace {

struct Job {
  const std::function<Status(RenderState&)>* work = nullptr;
  std::promise<Status> done;
};

Status RunGuarded(const std::function<Status(RenderState&)>& work, RenderState& state) {
  try {
    return work(state);
  } catch (const std::bad_alloc&) {
    return ResourceExhausted("raster: out of memory");
  } catch (const std::exception& e) {
    return Internal(std::string("raster: ") + e.what());
  }
}

}  // namespace

struct RasterRenderer::Impl {
  std::thread thread;
  std::mutex mutex;
  std::condition_variable wake;
  std::deque<Job> jobs;
  bool stopping = false;
  std::string gl_renderer, gl_version, platform;
  uint32_t max_side = 0;

  // The render thread: sets up the context, reports how that went, then serves jobs until told to stop.
  void Serve(const RendererOptions& options, std::promise<Status>& ready) {
    auto context = gl::EglContext::CreateCurrent();
    if (!context.ok()) {
      ready.set_value(Status(context.status().code(), "raster: " + context.status().message()));
      return;
    }
    auto state = RenderState::Create(options);
    if (!state.ok()) {
      ready.set_value(state.status());
      return;
    }
    gl_renderer = (*state)->caps.renderer;
    gl_version = (*state)->caps.version;
    max_side = (*state)->caps.max_side;
    platform = (*context)->platform();
    ready.set_value(Status::Ok());

    for (;;) {
      std::unique_lock lock(mutex);
      wake.wait(lock, [&] { return stopping || !jobs.empty(); });
      if (jobs.empty()) break;
      Job job = std::move(jobs.front());
      jobs.pop_front();
      lock.unlock();
      job.done.set_value(RunGuarded(*job.work, **state));
    }
    state->reset();  // GL objects go before the context
  }
};

RasterRenderer::RasterRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

StatusOr<std::unique_ptr<RasterRenderer>> RasterRenderer::Create(const RendererOptions& options) {
  auto impl = std::make_unique<Impl>();
  std::promise<Status> ready;
  std::future<Status> started = ready.get_future();
  Impl* raw = impl.get();
  impl->thread = std::thread([raw, options, &ready] { raw->Serve(options, ready); });
  Status status = started.get();
  if (!status.ok()) {
    impl->thread.join();
    return status;
  }
  return std::unique_ptr<RasterRenderer>(new RasterRenderer(std::move(impl)));
}

RasterRenderer::~RasterRenderer() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->wake.notify_one();
  impl_->thread.join();
}

const std::string& RasterRenderer::gl_renderer() const { return impl_->gl_renderer; }
const std::string& RasterRenderer::gl_version() const { return impl_->gl_version; }
const std::string& RasterRenderer::platform() const { return impl_->platform; }
uint32_t RasterRenderer::max_side() const { return impl_->max_side; }

Status RasterRenderer::Run(const std::function<Status(RenderState&)>& work) {
  std::future<Status> done;
  {
    std::lock_guard lock(impl_->mutex);
    if (impl_->stopping) return Unavailable("raster: renderer is shutting down");
    impl_->jobs.push_back(Job{&work, {}});
    done = impl_->jobs.back().done.get_future();
  }
  impl_->wake.notify_one();
  return done.get();
}

void RasterRenderer::Evict(const std::string& key) {
  // Fails only while shutting down, when the cache goes with the renderer anyway.
  (void)Run([&](RenderState& state) {
    state.scenes.Evict(key);
    return Status::Ok();
  });
}

size_t RasterRenderer::cached_scene_count() {
  size_t count = 0;
  // Fails only while shutting down; the count then stays 0.
  (void)Run([&](RenderState& state) {
    count = state.scenes.size();
    return Status::Ok();
  });
  return count;
}

}  // namespace vscan::raster

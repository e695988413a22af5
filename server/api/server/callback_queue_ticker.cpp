#include "api/server/callback_queue_ticker.h"

#include <future>

#include <grpcpp/client_context.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/support/byte_buffer.h>
#include <grpcpp/support/channel_arguments.h>

namespace vscan::api {

CallbackQueueTicker::CallbackQueueTicker(grpc::Server& server, std::chrono::milliseconds period)
    : period_(period), channel_(server.InProcessChannel(grpc::ChannelArguments())), thread_([this] { Run(); }) {}

CallbackQueueTicker::~CallbackQueueTicker() { Stop(); }

void CallbackQueueTicker::Stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

uint64_t CallbackQueueTicker::ticks() const {
  std::lock_guard lock(mutex_);
  return ticks_;
}

void CallbackQueueTicker::Run() {
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, period_, [this] { return stop_; })) {
    lock.unlock();
    const bool ok = Tick();
    lock.lock();
    if (ok) ++ticks_;
  }
}

// An empty HealthCheckRequest (service "", the server as a whole), waited for.
bool CallbackQueueTicker::Tick() {
  grpc::GenericStub stub(channel_);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(1));
  context.AddMetadata(kTickHeader, "1");
  grpc::Slice empty;
  const grpc::ByteBuffer request(&empty, 1);
  grpc::ByteBuffer response;
  // Shared with the callback, which may still be returning from set_value when get() does.
  auto answered = std::make_shared<std::promise<bool>>();
  std::future<bool> ok = answered->get_future();
  stub.UnaryCall(&context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, &response,
                 [answered](const grpc::Status& status) { answered->set_value(status.ok()); });
  return ok.get();
}

}  // namespace vscan::api

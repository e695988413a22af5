#include "api/server/callback_queue_ticker.h"

#include <chrono>
#include <thread>

#include <grpcpp/generic/async_generic_service.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/server_builder.h>
#include <gtest/gtest.h>

namespace vscan::api {
namespace {

// A callback service (any) makes the server run on the callback queue, as vscand does.
class CallbackQueueTickerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    grpc::EnableDefaultHealthCheckService(true);
    grpc::ServerBuilder builder;
    builder.RegisterCallbackGenericService(&generic_);
    server_ = builder.BuildAndStart();
    ASSERT_NE(server_, nullptr);
  }
  void TearDown() override {
    if (server_) server_->Shutdown();
  }

  grpc::CallbackGenericService generic_;
  std::unique_ptr<grpc::Server> server_;
};

// Waits (bounded) until the ticker has had n answers.
bool WaitForTicks(const CallbackQueueTicker& ticker, uint64_t n) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (ticker.ticks() < n && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return ticker.ticks() >= n;
}

TEST_F(CallbackQueueTickerTest, ChecksTheServerHealthRepeatedly) {
  CallbackQueueTicker ticker(*server_, std::chrono::milliseconds(1));
  EXPECT_TRUE(WaitForTicks(ticker, 3));
}

TEST_F(CallbackQueueTickerTest, StopsPromptlyAndTwice) {
  CallbackQueueTicker ticker(*server_, std::chrono::hours(1));
  ticker.Stop();
  ticker.Stop();
  EXPECT_EQ(ticker.ticks(), 0u);
}

}  // namespace
}  // namespace vscan::api

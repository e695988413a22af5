// The stall watchdog: what is not disarmed within the limit fires once, on the watchdog's thread
// and without its lock (so on_stall may arm and disarm); what is disarmed never fires.

#include "guards/stall_watchdog.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <thread>

namespace vscan::guards {
namespace {

using namespace std::chrono_literals;
using Clock = StallWatchdog::Clock;

TEST(StallWatchdogTest, FiresOnceAfterTheLimitOnItsOwnThread) {
  StallWatchdog watchdog(50ms);
  std::promise<std::thread::id> fired;
  std::atomic<int> calls = 0;
  const auto start = Clock::now();
  watchdog.Arm([&] {
    if (calls++ == 0) fired.set_value(std::this_thread::get_id());
  });
  auto thread = fired.get_future();
  ASSERT_EQ(thread.wait_for(10s), std::future_status::ready);
  EXPECT_GE(Clock::now() - start, 50ms);
  EXPECT_NE(thread.get(), std::this_thread::get_id());
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(calls.load(), 1);
}

TEST(StallWatchdogTest, DisarmedInTimeNeverFires) {
  StallWatchdog watchdog(500ms);
  std::atomic<bool> disarmed_fired = false;
  const uint64_t id = watchdog.Arm([&] { disarmed_fired = true; });
  watchdog.Disarm(id);
  // Armed later, so due later: once it has fired, the disarmed one would have too.
  std::promise<void> later;
  watchdog.Arm([&] { later.set_value(); });
  ASSERT_EQ(later.get_future().wait_for(10s), std::future_status::ready);
  EXPECT_FALSE(disarmed_fired.load());
}

TEST(StallWatchdogTest, OnStallMayArmAndDisarm) {
  StallWatchdog watchdog(20ms);
  std::promise<void> second;
  watchdog.Arm([&] {
    watchdog.Disarm(watchdog.Arm([] {}));
    watchdog.Arm([&] { second.set_value(); });
  });
  EXPECT_EQ(second.get_future().wait_for(10s), std::future_status::ready);
}

TEST(StallWatchdogTest, EveryArmedOperationFiresExactlyOnce) {
  StallWatchdog watchdog(10ms);
  constexpr int kCount = 200;
  std::atomic<int> fired = 0;
  std::promise<void> all;
  for (int i = 0; i < kCount; ++i) {
    watchdog.Arm([&] {
      if (++fired == kCount) all.set_value();
    });
  }
  ASSERT_EQ(all.get_future().wait_for(10s), std::future_status::ready);
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(fired.load(), kCount);
}

TEST(StallWatchdogTest, StopIsPromptAndDropsWhatIsArmed) {
  auto watchdog = std::make_unique<StallWatchdog>(1h);
  auto owned = std::make_shared<int>(0);
  std::atomic<bool> fired = false;
  watchdog->Arm([&fired, owned] { fired = true; });
  EXPECT_EQ(owned.use_count(), 2);
  const auto start = Clock::now();
  watchdog->Stop();
  EXPECT_LT(Clock::now() - start, 5s);
  EXPECT_EQ(owned.use_count(), 1);
  watchdog.reset();
  EXPECT_FALSE(fired.load());
}

}  // namespace
}  // namespace vscan::guards

// Log lines in both formats carry the request id and fields the thread has set; request ids follow
// work onto worker pools and job threads.

#include <future>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <spdlog/logger.h>
#include <spdlog/sinks/ostream_sink.h>

#include "jobs/job_runner.h"
#include "jobs/worker_pool.h"
#include "observability/log_fields.h"
#include "observability/log_format.h"
#include "observability/request_id.h"

namespace vscan::observability {
namespace {

class CapturedLog {
 public:
  explicit CapturedLog(LogFormat format)
      : logger_("vscand", std::make_shared<spdlog::sinks::ostream_sink_mt>(out_)) {
    logger_.set_formatter(MakeLogFormatter(format));
  }
  spdlog::logger& logger() { return logger_; }
  std::string text() const { return out_.str(); }

 private:
  std::ostringstream out_;
  spdlog::logger logger_;
};

TEST(ObservabilityLogFormat, JsonLineHasTimeLevelMessageRequestIdAndFields) {
  CapturedLog log(LogFormat::kJson);
  {
    RequestIdScope id("req-42");
    LogFieldsScope fields({{"method", "/vscan.v1.ScanService/Scan"}, {"duration_ms", "1.5", true}});
    log.logger().info("scan of \"{}\"\tdone\n", "box");
  }
  log.logger().warn("no call");
  const std::regex expected(
      R"(\{"time":"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z","level":"info","logger":"vscand","thread":\d+,)"
      R"("message":"scan of \\"box\\"\\tdone\\n","request_id":"req-42",)"
      R"("method":"/vscan.v1.ScanService/Scan","duration_ms":1.5\}\n)"
      R"(\{"time":"[^"]+","level":"warning","logger":"vscand","thread":\d+,"message":"no call"\}\n)");
  EXPECT_TRUE(std::regex_match(log.text(), expected)) << log.text();
}

TEST(ObservabilityLogFormat, TextLineNamesTheRequestAndFields) {
  CapturedLog log(LogFormat::kText);
  {
    RequestIdScope id("abc");
    LogFieldsScope fields({LogField{"code", "OK"}});
    log.logger().info("call ended");
  }
  log.logger().info("idle");
  const std::regex expected(R"(\S+ info \[vscand\] \[req abc\] call ended code=OK\n)"
                            R"(\S+ info \[vscand\] idle\n)");
  EXPECT_TRUE(std::regex_match(log.text(), expected)) << log.text();
}

TEST(ObservabilityLogFormat, ParsesFormatNames) {
  EXPECT_EQ(ParseLogFormat("json"), LogFormat::kJson);
  EXPECT_EQ(ParseLogFormat("text"), LogFormat::kText);
  EXPECT_FALSE(ParseLogFormat("xml").has_value());
}

TEST(ObservabilityRequestId, ScopesNestAndRestore) {
  EXPECT_EQ(CurrentRequestId(), "");
  {
    RequestIdScope outer("a");
    {
      RequestIdScope inner("b");
      EXPECT_EQ(CurrentRequestId(), "b");
    }
    EXPECT_EQ(CurrentRequestId(), "a");
  }
  EXPECT_EQ(CurrentRequestId(), "");
}

TEST(ObservabilityRequestId, FreshIdsAreSaneAndDistinct) {
  const std::string a = NewRequestId();
  const std::string b = NewRequestId();
  EXPECT_EQ(a.size(), 16u);
  EXPECT_NE(a, b);
  EXPECT_TRUE(IsSaneRequestId(a));
  EXPECT_TRUE(IsSaneRequestId("client-7:retry_2.x"));
  EXPECT_FALSE(IsSaneRequestId(""));
  EXPECT_FALSE(IsSaneRequestId("has space"));
  EXPECT_FALSE(IsSaneRequestId("quote\""));
  EXPECT_FALSE(IsSaneRequestId(std::string(65, 'a')));
}

TEST(ObservabilityRequestId, WorkerPoolAndJobRunnerCarryThePostersId) {
  std::string seen_by_worker = "unset";
  std::string seen_by_job = "unset";
  std::promise<std::string> job_done;
  {
    jobs::WorkerPool pool(1);
    jobs::JobRunner runner(1);
    {
      RequestIdScope id("poster");
      ASSERT_TRUE(pool.Post([&] { seen_by_worker = CurrentRequestId(); }));
      ASSERT_TRUE(runner.Submit(
          "job", [&](jobs::JobControl&) { job_done.set_value(CurrentRequestId()); }, nullptr, 1));
    }
    seen_by_job = job_done.get_future().get();
    std::string after = "unset";
    ASSERT_TRUE(pool.Post([&] { after = CurrentRequestId(); }));
    pool.Stop();
    runner.Stop();
    EXPECT_EQ(after, "");
  }
  EXPECT_EQ(seen_by_worker, "poster");
  EXPECT_EQ(seen_by_job, "poster");
}

}  // namespace
}  // namespace vscan::observability

// The Prometheus text rendering of a registry, checked line for line.

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "observability/metrics.h"

namespace vscan::observability {
namespace {

TEST(MetricsText, RendersCountersGaugesAndHistogramsExactly) {
  Registry registry;
  auto& calls = registry.AddCounter("calls_total", "Calls by method\nand code", {"method", "code"});
  auto& temperature = registry.AddGauge("temperature_celsius", "Current temperature");
  auto& latency = registry.AddHistogram("latency_seconds", "Call latency", {"method"}, {0.5, 1, 4});

  calls.WithLabels({"Scan", "OK"}).Increment();
  calls.WithLabels({"Scan", "OK"}).Increment(2);
  calls.WithLabels({"Get\"\\x", "NOT_FOUND"}).Increment();
  temperature.WithLabels({}).Set(-1.5);
  auto& scan = latency.WithLabels({"Scan"});
  for (const double seconds : {0.25, 0.5, 2.0, 16.0}) scan.Observe(seconds);

  const std::string expected =
      "# HELP calls_total Calls by method\\nand code\n"
      "# TYPE calls_total counter\n"
      "calls_total{method=\"Get\\\"\\\\x\",code=\"NOT_FOUND\"} 1\n"
      "calls_total{method=\"Scan\",code=\"OK\"} 3\n"
      "# HELP temperature_celsius Current temperature\n"
      "# TYPE temperature_celsius gauge\n"
      "temperature_celsius -1.5\n"
      "# HELP latency_seconds Call latency\n"
      "# TYPE latency_seconds histogram\n"
      "latency_seconds_bucket{method=\"Scan\",le=\"0.5\"} 2\n"
      "latency_seconds_bucket{method=\"Scan\",le=\"1\"} 2\n"
      "latency_seconds_bucket{method=\"Scan\",le=\"4\"} 3\n"
      "latency_seconds_bucket{method=\"Scan\",le=\"+Inf\"} 4\n"
      "latency_seconds_sum{method=\"Scan\"} 18.75\n"
      "latency_seconds_count{method=\"Scan\"} 4\n";
  EXPECT_EQ(registry.Render(), expected);
}

TEST(MetricsText, HistogramWithoutLabelsHasItsEmptySeriesFromTheStart) {
  Registry registry;
  registry.AddHistogram("size_bytes", "Sizes", {}, {10, 100});
  EXPECT_EQ(registry.Render(),
            "# HELP size_bytes Sizes\n"
            "# TYPE size_bytes histogram\n"
            "size_bytes_bucket{le=\"10\"} 0\n"
            "size_bytes_bucket{le=\"100\"} 0\n"
            "size_bytes_bucket{le=\"+Inf\"} 0\n"
            "size_bytes_sum 0\n"
            "size_bytes_count 0\n");
}

TEST(MetricsText, HistogramBucketsAreCumulativeAndBoundsInclusive) {
  Histogram histogram({1, 2, 3});
  for (const double value : {0.0, 1.0, 1.5, 2.0, 2.0, 3.5, 100.0}) histogram.Observe(value);
  // Not cumulative here: (-inf,1], (1,2], (2,3], (3,inf).
  EXPECT_EQ(histogram.bucket_counts(), (std::vector<uint64_t>{2, 3, 0, 2}));
  EXPECT_EQ(histogram.count(), 7u);
  EXPECT_DOUBLE_EQ(histogram.sum(), 110.0);

  Registry registry;
  auto& family = registry.AddHistogram("h", "H", {}, {1, 2, 3});
  for (const double value : {0.0, 1.0, 1.5, 2.0, 2.0, 3.5, 100.0}) family.WithLabels({}).Observe(value);
  const std::string text = registry.Render();
  EXPECT_NE(text.find("h_bucket{le=\"1\"} 2\n"), std::string::npos);
  EXPECT_NE(text.find("h_bucket{le=\"2\"} 5\n"), std::string::npos);
  EXPECT_NE(text.find("h_bucket{le=\"3\"} 5\n"), std::string::npos);
  EXPECT_NE(text.find("h_bucket{le=\"+Inf\"} 7\n"), std::string::npos);
  EXPECT_NE(text.find("h_count 7\n"), std::string::npos);
}

TEST(MetricsText, CollectedGaugesAreComputedAtRenderAndCanBeRemoved) {
  Registry registry;
  int calls = 0;
  const int id = registry.AddGaugeCollector("jobs", "Jobs", {"kind", "state"}, [&calls] {
    ++calls;
    return std::vector<GaugeSample>{{{"campaign", "running"}, 1}, {{"model", "queued"}, 2}};
  });
  EXPECT_EQ(registry.Render(),
            "# HELP jobs Jobs\n"
            "# TYPE jobs gauge\n"
            "jobs{kind=\"campaign\",state=\"running\"} 1\n"
            "jobs{kind=\"model\",state=\"queued\"} 2\n");
  EXPECT_EQ(calls, 1);
  registry.RemoveCollector(id);
  EXPECT_EQ(registry.Render(), "");
}

TEST(MetricsText, RejectsBadNamesRepeatsAndMisuse) {
  Registry registry;
  EXPECT_THROW(registry.AddCounter("1bad", "x"), std::invalid_argument);
  EXPECT_THROW(registry.AddCounter("ok_total", "x", {"bad-label"}), std::invalid_argument);
  EXPECT_THROW(registry.AddHistogram("h", "x", {"le"}, {1}), std::invalid_argument);
  EXPECT_THROW(registry.AddHistogram("h", "x", {}, {2, 1}), std::invalid_argument);
  auto& counter = registry.AddCounter("ok_total", "x", {"a"});
  EXPECT_THROW(registry.AddGauge("ok_total", "x"), std::invalid_argument);
  EXPECT_THROW(counter.WithLabels({"1", "2"}), std::invalid_argument);
  EXPECT_THROW(counter.WithLabels({"1"}).Increment(-1), std::invalid_argument);
}

TEST(MetricsText, ExponentialBucketsMultiply) {
  EXPECT_EQ(ExponentialBuckets(0.5, 2, 4), (std::vector<double>{0.5, 1, 2, 4}));
}

}  // namespace
}  // namespace vscan::observability

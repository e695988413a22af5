#include "observability/metrics.h"

#include <algorithm>
#include <cmath>
#include <regex>
#include <stdexcept>

namespace vscan::observability {
namespace {

void AtomicAdd(std::atomic<double>& target, double amount) {
  double current = target.load(std::memory_order_relaxed);
  while (!target.compare_exchange_weak(current, current + amount, std::memory_order_relaxed)) {
  }
}

void CheckName(const std::string& name, const std::regex& pattern, const char* what) {
  if (!std::regex_match(name, pattern)) throw std::invalid_argument(std::string("invalid metric ") + what + ": " + name);
}

}  // namespace

void Counter::Increment(double amount) {
  if (amount < 0) throw std::invalid_argument("a counter cannot decrease");
  AtomicAdd(value_, amount);
}

void Gauge::Add(double amount) { AtomicAdd(value_, amount); }

Histogram::Histogram(std::vector<double> upper_bounds)
    : upper_bounds_(std::move(upper_bounds)),
      buckets_(std::make_unique<std::atomic<uint64_t>[]>(upper_bounds_.size() + 1)) {
  for (size_t i = 0; i < upper_bounds_.size(); ++i) {
    if (!std::isfinite(upper_bounds_[i]) || (i > 0 && upper_bounds_[i] <= upper_bounds_[i - 1])) {
      throw std::invalid_argument("histogram bounds must be finite and increasing");
    }
  }
  for (size_t i = 0; i <= upper_bounds_.size(); ++i) buckets_[i].store(0, std::memory_order_relaxed);
}

void Histogram::Observe(double value) {
  // A value equal to a bound belongs to that bound's bucket (le: less or equal).
  const auto bucket = std::lower_bound(upper_bounds_.begin(), upper_bounds_.end(), value) - upper_bounds_.begin();
  buckets_[static_cast<size_t>(bucket)].fetch_add(1, std::memory_order_relaxed);
  AtomicAdd(sum_, value);
  count_.fetch_add(1, std::memory_order_relaxed);
}

std::vector<uint64_t> Histogram::bucket_counts() const {
  std::vector<uint64_t> counts(upper_bounds_.size() + 1);
  for (size_t i = 0; i < counts.size(); ++i) counts[i] = buckets_[i].load(std::memory_order_relaxed);
  return counts;
}

std::vector<double> ExponentialBuckets(double start, double factor, int count) {
  std::vector<double> bounds;
  double bound = start;
  for (int i = 0; i < count; ++i, bound *= factor) bounds.push_back(bound);
  return bounds;
}

Registry::Entry& Registry::Add(const std::string& name, const std::string& help, MetricType type,
                               const std::vector<std::string>& labels) {
  static const std::regex kMetricName("[a-zA-Z_:][a-zA-Z0-9_:]*");
  static const std::regex kLabelName("[a-zA-Z_][a-zA-Z0-9_]*");
  CheckName(name, kMetricName, "name");
  for (const std::string& label : labels) {
    CheckName(label, kLabelName, "label name");
    if (label == "le") throw std::invalid_argument("the label name le is reserved for histogram buckets");
  }
  for (const auto& entry : entries_) {
    if (entry->name == name) throw std::invalid_argument("metric registered twice: " + name);
  }
  auto entry = std::make_unique<Entry>();
  entry->name = name;
  entry->help = help;
  entry->type = type;
  entries_.push_back(std::move(entry));
  return *entries_.back();
}

Family<Counter>& Registry::AddCounter(const std::string& name, const std::string& help,
                                      std::vector<std::string> labels) {
  std::lock_guard lock(mutex_);
  Entry& entry = Add(name, help, MetricType::kCounter, labels);
  entry.counters = std::make_unique<Family<Counter>>(std::move(labels), [] { return std::make_unique<Counter>(); });
  if (entry.counters->label_names().empty()) entry.counters->WithLabels({});
  return *entry.counters;
}

Family<Gauge>& Registry::AddGauge(const std::string& name, const std::string& help, std::vector<std::string> labels) {
  std::lock_guard lock(mutex_);
  Entry& entry = Add(name, help, MetricType::kGauge, labels);
  entry.gauges = std::make_unique<Family<Gauge>>(std::move(labels), [] { return std::make_unique<Gauge>(); });
  if (entry.gauges->label_names().empty()) entry.gauges->WithLabels({});
  return *entry.gauges;
}

Family<Histogram>& Registry::AddHistogram(const std::string& name, const std::string& help,
                                          std::vector<std::string> labels, std::vector<double> upper_bounds) {
  std::lock_guard lock(mutex_);
  Entry& entry = Add(name, help, MetricType::kHistogram, labels);
  Histogram check(upper_bounds);  // throws on bad bounds here rather than on first use
  entry.histograms = std::make_unique<Family<Histogram>>(
      std::move(labels), [bounds = std::move(upper_bounds)] { return std::make_unique<Histogram>(bounds); });
  if (entry.histograms->label_names().empty()) entry.histograms->WithLabels({});
  return *entry.histograms;
}

int Registry::AddGaugeCollector(const std::string& name, const std::string& help, std::vector<std::string> labels,
                                GaugeCollector collect) {
  std::lock_guard lock(mutex_);
  Entry& entry = Add(name, help, MetricType::kGauge, labels);
  entry.collector_labels = std::move(labels);
  entry.collector = std::move(collect);
  entry.collector_id = next_collector_id_++;
  return entry.collector_id;
}

void Registry::RemoveCollector(int id) {
  std::lock_guard lock(mutex_);
  std::erase_if(entries_, [id](const auto& entry) { return entry->collector && entry->collector_id == id; });
}

}  // namespace vscan::observability

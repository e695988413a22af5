// Registry::Render: the Prometheus text exposition format, version 0.0.4.

#include <charconv>
#include <cmath>
#include <string>

#include "observability/metrics.h"

namespace vscan::observability {
namespace {

std::string FormatValue(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

// HELP text escapes backslash and newline; label values also escape the double quote.
std::string Escape(const std::string& text, bool quote) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else if (quote && c == '"') {
      out += "\\\"";
    } else {
      out += c;
    }
  }
  return out;
}

// {a="x",b="y"}, with an optional extra label last (le of a bucket); empty without labels.
std::string LabelSet(const std::vector<std::string>& names, const std::vector<std::string>& values,
                     const std::string& extra_name = "", const std::string& extra_value = "") {
  std::string out;
  for (size_t i = 0; i < names.size() && i < values.size(); ++i) {
    out += out.empty() ? "{" : ",";
    out += names[i] + "=\"" + Escape(values[i], true) + "\"";
  }
  if (!extra_name.empty()) {
    out += out.empty() ? "{" : ",";
    out += extra_name + "=\"" + extra_value + "\"";
  }
  if (!out.empty()) out += "}";
  return out;
}

void Sample(std::string& out, const std::string& name, const std::string& labels, double value) {
  out += name;
  out += labels;
  out += ' ';
  out += FormatValue(value);
  out += '\n';
}

void RenderHistogram(std::string& out, const std::string& name, const std::vector<std::string>& names,
                     const std::vector<std::string>& values, const Histogram& histogram) {
  const std::vector<uint64_t> counts = histogram.bucket_counts();
  uint64_t cumulative = 0;
  for (size_t i = 0; i < counts.size(); ++i) {
    cumulative += counts[i];
    const bool last = i + 1 == counts.size();
    const std::string le = last ? "+Inf" : FormatValue(histogram.upper_bounds()[i]);
    Sample(out, name + "_bucket", LabelSet(names, values, "le", le), static_cast<double>(cumulative));
  }
  Sample(out, name + "_sum", LabelSet(names, values), histogram.sum());
  // The +Inf bucket's count, so that _count and the buckets agree under concurrent updates.
  Sample(out, name + "_count", LabelSet(names, values), static_cast<double>(cumulative));
}

}  // namespace

std::string Registry::Render() const {
  std::lock_guard lock(mutex_);
  std::string out;
  for (const auto& entry : entries_) {
    out += "# HELP " + entry->name + " " + Escape(entry->help, false) + "\n";
    out += "# TYPE " + entry->name + " ";
    switch (entry->type) {
      case MetricType::kCounter: out += "counter\n"; break;
      case MetricType::kGauge: out += "gauge\n"; break;
      case MetricType::kHistogram: out += "histogram\n"; break;
    }
    if (entry->counters) {
      const auto& names = entry->counters->label_names();
      entry->counters->ForEach([&](const std::vector<std::string>& values, const Counter& counter) {
        Sample(out, entry->name, LabelSet(names, values), counter.value());
      });
    } else if (entry->gauges) {
      const auto& names = entry->gauges->label_names();
      entry->gauges->ForEach([&](const std::vector<std::string>& values, const Gauge& gauge) {
        Sample(out, entry->name, LabelSet(names, values), gauge.value());
      });
    } else if (entry->histograms) {
      const auto& names = entry->histograms->label_names();
      entry->histograms->ForEach([&](const std::vector<std::string>& values, const Histogram& histogram) {
        RenderHistogram(out, entry->name, names, values, histogram);
      });
    } else if (entry->collector) {
      for (const GaugeSample& sample : entry->collector()) {
        Sample(out, entry->name, LabelSet(entry->collector_labels, sample.label_values), sample.value);
      }
    }
  }
  return out;
}

}  // namespace vscan::observability

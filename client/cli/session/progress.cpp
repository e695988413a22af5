#include "session/progress.h"

#include <cstdio>

#include <unistd.h>

namespace vscan::cli {
namespace {

constexpr int kBarWidth = 30;
constexpr auto kRedrawInterval = std::chrono::milliseconds(100);

}  // namespace

ProgressBar::ProgressBar(std::string label, std::string unit, bool enabled)
    : label_(std::move(label)), unit_(std::move(unit)), enabled_(enabled && ::isatty(STDERR_FILENO) != 0) {}

ProgressBar::~ProgressBar() { Finish(); }

void ProgressBar::Update(uint64_t done, uint64_t total) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  // Always draw the final state; throttle the rest.
  if (drawn_ && now - last_draw_ < kRedrawInterval && (total == 0 || done < total)) return;
  last_draw_ = now;
  Draw(done, total);
}

void ProgressBar::Draw(uint64_t done, uint64_t total) {
  std::string bar;
  if (total > 0) {
    const double fraction = done >= total ? 1.0 : static_cast<double>(done) / static_cast<double>(total);
    const int filled = static_cast<int>(fraction * kBarWidth);
    bar.append("[").append(filled, '#').append(kBarWidth - filled, '-').append("]");
    std::fprintf(stderr, "\r%s %s %5.1f%% %llu/%llu %s", label_.c_str(), bar.c_str(), fraction * 100.0,
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total), unit_.c_str());
  } else {
    std::fprintf(stderr, "\r%s %llu %s", label_.c_str(), static_cast<unsigned long long>(done), unit_.c_str());
  }
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::Finish() {
  if (!drawn_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace vscan::cli

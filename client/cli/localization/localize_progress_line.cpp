#include "localization/localize_progress_line.h"

#include <algorithm>
#include <cstdio>

namespace vscan::cli {

void LocalizeProgressLine::Update(const v1::LocalizeProgress& progress) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double percent = std::clamp(progress.fraction(), 0.0, 1.0) * 100;
  const auto found = static_cast<unsigned long long>(progress.found());
  if (terminal_) {
    std::fprintf(stderr, "\r\033[Klocalizing %5.1f%%, %llu found, %.1f s: %s", percent, found, seconds,
                 progress.stage().c_str());
    drawn_ = true;
  } else if (progress.stage() != last_stage_) {
    std::fprintf(stderr, "localizing %5.1f%%, %llu found, %.1f s: %s\n", percent, found, seconds,
                 progress.stage().c_str());
  }
  last_stage_ = progress.stage();
  std::fflush(stderr);
}

void LocalizeProgressLine::Finish() {
  if (!drawn_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace vscan::cli

#include "api/validate.h"

#include <algorithm>
#include <cmath>

namespace vscan::api {
namespace {

constexpr int kDefaultPageSize = 100;

}  // namespace

Status RequireId(const std::string& id, std::string_view field) {
  if (id.empty()) return InvalidArgument(std::string(field), "required");
  if (id.size() > 64) return InvalidArgument(std::string(field), "longer than 64 characters");
  return Status::Ok();
}

Status CheckText(const std::string& text, std::string_view field, size_t max_length) {
  if (text.size() > max_length) {
    return InvalidArgument(std::string(field), "longer than " + std::to_string(max_length) + " bytes");
  }
  return Status::Ok();
}

StatusOr<double> ScaleOrDefault(double scale, std::string_view field) {
  if (scale == 0.0) return 1.0;
  if (!std::isfinite(scale) || scale < 0 || scale > 1e6) {
    return InvalidArgument(std::string(field), "must be a finite number in (0, 1e6]");
  }
  return scale;
}

StatusOr<int> PageSize(int32_t page_size, uint32_t max_page_size) {
  if (page_size < 0) return InvalidArgument("page_size", "must not be negative");
  if (page_size == 0) return std::min<int>(kDefaultPageSize, static_cast<int>(max_page_size));
  return std::min<int>(page_size, static_cast<int>(max_page_size));
}

}  // namespace vscan::api

#include "ascii_records.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "vscan/common/text_excerpt.h"

namespace vscan::cloud_records {
namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

template <typename T>
bool StoreInteger(double v, char* out) {
  if (!(v >= static_cast<double>(std::numeric_limits<T>::min()) &&
        v <= static_cast<double>(std::numeric_limits<T>::max()) && v == std::floor(v))) {
    return false;
  }
  const T t = static_cast<T>(v);
  std::memcpy(out, &t, sizeof(T));
  return true;
}

template <typename T>
bool StoreFloat(double v, char* out) {
  const T t = static_cast<T>(v);
  std::memcpy(out, &t, sizeof(T));
  return true;
}

// Stores v in the property's type; false when it does not fit (or is not whole, for integers).
bool Store(double v, ScalarType type, char* out) {
  switch (type) {
    case ScalarType::kInt8: return StoreInteger<int8_t>(v, out);
    case ScalarType::kUint8: return StoreInteger<uint8_t>(v, out);
    case ScalarType::kInt16: return StoreInteger<int16_t>(v, out);
    case ScalarType::kUint16: return StoreInteger<uint16_t>(v, out);
    case ScalarType::kInt32: return StoreInteger<int32_t>(v, out);
    case ScalarType::kUint32: return StoreInteger<uint32_t>(v, out);
    // 64-bit integers pass through a double: exact up to 2^53, which every field vscan reads fits.
    case ScalarType::kInt64: return StoreInteger<int64_t>(v, out);
    case ScalarType::kUint64: return StoreInteger<uint64_t>(v, out);
    case ScalarType::kFloat32: return StoreFloat<float>(v, out);
    case ScalarType::kFloat64: return StoreFloat<double>(v, out);
  }
  return false;
}

// A number as PCL and Open3D print them: decimal, exponent, "nan", "inf", an optional sign.
bool ParseNumber(std::string_view token, double* v) {
  if (token.starts_with('+')) token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), *v);
  return ec == std::errc() && end == token.data() + token.size();
}

}  // namespace

AsciiRecords::AsciiRecords(std::string_view text, const RecordLayout& layout, std::string path, std::string what)
    : text_(text), layout_(layout), path_(std::move(path)), what_(std::move(what)) {
  for (const RecordProperty& p : layout_.properties) values_per_record_ += p.count;
}

Status AsciiRecords::CheckRoom(size_t records, size_t values) const {
  const size_t room = (text_.size() - at_ + 1) / 2;  // "v v v" holds (size + 1) / 2 values at most
  if (values > room || (values_per_record_ != 0 && records > (room - values) / values_per_record_)) {
    return DataLoss(path_ + ": truncated: " + std::to_string(records) + " " + what_ + " records of " +
                    std::to_string(values_per_record_) + " values cannot fit in the " +
                    std::to_string(text_.size() - at_) + " bytes of text left");
  }
  return Status::Ok();
}

std::string_view AsciiRecords::Next() {
  while (at_ < text_.size() && IsSpace(text_[at_])) ++at_;
  const size_t begin = at_;
  while (at_ < text_.size() && !IsSpace(text_[at_])) ++at_;
  return text_.substr(begin, at_ - begin);
}

Status AsciiRecords::Skip(size_t values) {
  for (size_t i = 0; i < values; ++i) {
    if (Next().empty()) return DataLoss(path_ + ": truncated: the text ends before the " + what_ + " records");
  }
  return Status::Ok();
}

Status AsciiRecords::Fill(char* out, size_t first, size_t points) {
  for (size_t k = 0; k < points; ++k) {
    char* record = out + k * layout_.stride;
    for (const RecordProperty& p : layout_.properties) {
      const size_t size = ScalarSize(p.type);
      for (size_t c = 0; c < p.count; ++c) {
        const std::string_view token = Next();
        const auto where = [&] {
          return path_ + ": " + what_ + " " + std::to_string(first + k) + ", property '" + p.name + "'";
        };
        if (token.empty()) return DataLoss(where() + ": truncated: the text ends here");
        double v = 0;
        if (!ParseNumber(token, &v)) {
          return InvalidArgument(where() + ": '" + TextExcerpt(token, 32) + "' is not a number");
        }
        if (!Store(v, p.type, record + p.offset + c * size)) {
          return InvalidArgument(where() + ": " + std::string(token.substr(0, 32)) + " does not fit its type");
        }
      }
    }
  }
  return Status::Ok();
}

}  // namespace vscan::cloud_records

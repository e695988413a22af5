#pragma once
// Little-endian binary writing and bounds-checked reading for small stored records.

#include <bit>
#include <cstdint>
#include <string>
#include <string_view>

#include "vscan/common/status.h"

namespace vscan::store {

class ByteWriter {
 public:
  void U32(uint32_t v) { Fixed(v, 4); }
  void U64(uint64_t v) { Fixed(v, 8); }
  void F64(double v) { Fixed(std::bit_cast<uint64_t>(v), 8); }
  // A u64 length, then the bytes.
  void Bytes(std::string_view bytes) {
    U64(bytes.size());
    out_.append(bytes);
  }
  void Raw(std::string_view bytes) { out_.append(bytes); }

  const std::string& str() const { return out_; }
  std::string Take() { return std::move(out_); }

 private:
  void Fixed(uint64_t v, int size) {
    for (int b = 0; b < size; ++b) out_.push_back(static_cast<char>((v >> (8 * b)) & 0xff));
  }
  std::string out_;
};

// Every read fails with DATA_LOSS naming `what` once the input runs short.
class ByteReader {
 public:
  ByteReader(std::string_view in, std::string what) : in_(in), what_(std::move(what)) {}

  StatusOr<uint32_t> U32() {
    ASSIGN_OR_RETURN(uint64_t v, Fixed(4));
    return static_cast<uint32_t>(v);
  }
  StatusOr<uint64_t> U64() { return Fixed(8); }
  StatusOr<double> F64() {
    ASSIGN_OR_RETURN(uint64_t v, Fixed(8));
    return std::bit_cast<double>(v);
  }
  StatusOr<std::string_view> Bytes() {
    ASSIGN_OR_RETURN(uint64_t size, U64());
    return Raw(size);
  }
  StatusOr<std::string_view> Raw(uint64_t size) {
    if (size > in_.size()) return Short();
    std::string_view out = in_.substr(0, static_cast<size_t>(size));
    in_.remove_prefix(static_cast<size_t>(size));
    return out;
  }
  bool done() const { return in_.empty(); }
  size_t remaining() const { return in_.size(); }
  Status Short() const { return DataLoss(what_ + ": truncated or malformed"); }

 private:
  StatusOr<uint64_t> Fixed(int size) {
    if (in_.size() < static_cast<size_t>(size)) return Short();
    uint64_t v = 0;
    for (int b = 0; b < size; ++b) v |= uint64_t{static_cast<unsigned char>(in_[b])} << (8 * b);
    in_.remove_prefix(static_cast<size_t>(size));
    return v;
  }

  std::string_view in_;
  std::string what_;
};

}  // namespace vscan::store

#include "lzf_decode.h"

#include <cstdint>
#include <cstring>

namespace vscan::cloud_records {

bool LzfDecompress(std::string_view in, char* out, size_t out_size) {
  const auto* ip = reinterpret_cast<const uint8_t*>(in.data());
  const uint8_t* const in_end = ip + in.size();
  size_t op = 0;
  while (ip < in_end) {
    const unsigned ctrl = *ip++;
    if (ctrl < 32) {  // a literal run of ctrl + 1 bytes
      const size_t len = ctrl + 1;
      if (static_cast<size_t>(in_end - ip) < len || out_size - op < len) return false;
      std::memcpy(out + op, ip, len);
      ip += len;
      op += len;
      continue;
    }
    size_t len = ctrl >> 5;  // a back-reference: length - 2 in 3 bits, 7 meaning one more byte
    if (len == 7) {
      if (ip >= in_end) return false;
      len += *ip++;
    }
    len += 2;
    if (ip >= in_end) return false;
    const size_t distance = ((ctrl & 0x1fu) << 8) + *ip++ + 1;
    if (distance > op || out_size - op < len) return false;
    if (distance >= len) {
      std::memcpy(out + op, out + op - distance, len);
      op += len;
    } else {  // byte by byte: the run repeats what it writes
      for (size_t i = 0; i < len; ++i, ++op) out[op] = out[op - distance];
    }
  }
  return op == out_size;
}

}  // namespace vscan::cloud_records

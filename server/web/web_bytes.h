#pragma once
// The web view's binary layouts (meshes, clouds) are little-endian: values are appended as the
// machine holds them, which the assertion pins.

#include <bit>
#include <cstring>
#include <string>

namespace vscan::web {

static_assert(std::endian::native == std::endian::little, "the web view's layouts are written as the host stores them");

template <typename T>
void AppendBytesOf(std::string& out, const T& value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

}  // namespace vscan::web

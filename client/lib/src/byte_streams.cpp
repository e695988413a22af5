#include "byte_streams.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

namespace vscan::client {

StatusOr<ChunkSource> FileSource(const std::string& path, uint64_t* size) {
  std::error_code ec;
  *size = std::filesystem::file_size(path, ec);
  if (ec) return NotFound(path + ": " + ec.message());
  auto in = std::make_shared<std::ifstream>(path, std::ios::binary);
  if (!*in) return NotFound(path + ": cannot open: " + std::strerror(errno));
  return ChunkSource([in, path](char* buf, size_t n) -> StatusOr<size_t> {
    in->read(buf, static_cast<std::streamsize>(n));
    if (in->bad()) return DataLoss(path + ": read failed");
    return static_cast<size_t>(in->gcount());
  });
}

ChunkSource BytesSource(std::string_view bytes) {
  auto offset = std::make_shared<size_t>(0);
  return [bytes, offset](char* buf, size_t n) -> StatusOr<size_t> {
    const size_t take = std::min(n, bytes.size() - *offset);
    std::memcpy(buf, bytes.data() + *offset, take);
    *offset += take;
    return take;
  };
}

}  // namespace vscan::client

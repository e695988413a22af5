#include "physics/decomposition_store.h"

#include <unistd.h>

#include <array>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace vscan::physics {
namespace {

constexpr std::array<char, 8> kMagic = {'v', 's', 'c', 'p', 'c', 's', '0', '1'};
// A piece of a part has at most a few thousand hull points; more means a damaged file.
constexpr uint32_t kMaxPieces = 4096, kMaxPoints = 1 << 20;

std::string FileOf(const std::string& dir, uint64_t name) {
  char text[40];
  std::snprintf(text, sizeof text, "%016" PRIx64 ".pieces", name);
  return (std::filesystem::path(dir) / text).string();
}

template <typename T>
bool Read(std::istream& in, T& value) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&value), sizeof value));
}

template <typename T>
void Write(std::ostream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

}  // namespace

std::optional<ConvexPieceSet> LoadPieces(const std::string& dir, const PiecesKey& key) {
  std::ifstream in(FileOf(dir, key.name), std::ios::binary);
  if (!in) return std::nullopt;
  std::array<char, 8> magic{};
  PiecesKey stored;
  uint32_t count = 0;
  if (!Read(in, magic) || magic != kMagic || !Read(in, stored.name) || !Read(in, stored.check) ||
      !Read(in, stored.vertices) || !Read(in, stored.triangles) || !Read(in, count)) {
    return std::nullopt;
  }
  if (stored.name != key.name || stored.check != key.check || stored.vertices != key.vertices ||
      stored.triangles != key.triangles || count == 0 || count > kMaxPieces) {
    return std::nullopt;
  }
  ConvexPieceSet pieces(count);
  for (auto& piece : pieces) {
    uint32_t points = 0;
    if (!Read(in, points) || points == 0 || points > kMaxPoints) return std::nullopt;
    piece.resize(points);
    for (auto& p : piece) {
      if (!Read(in, p.x()) || !Read(in, p.y()) || !Read(in, p.z())) return std::nullopt;
    }
  }
  char extra = 0;
  if (in.read(&extra, 1)) return std::nullopt;  // longer than written: not ours
  return pieces;
}

bool StorePieces(const std::string& dir, const PiecesKey& key, const ConvexPieceSet& pieces) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  const std::string file = FileOf(dir, key.name);
  const std::string temporary = file + ".tmp" + std::to_string(getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return false;
    Write(out, kMagic);
    Write(out, key.name);
    Write(out, key.check);
    Write(out, key.vertices);
    Write(out, key.triangles);
    Write(out, static_cast<uint32_t>(pieces.size()));
    for (const auto& piece : pieces) {
      Write(out, static_cast<uint32_t>(piece.size()));
      for (const auto& p : piece) {
        Write(out, p.x());
        Write(out, p.y());
        Write(out, p.z());
      }
    }
    if (!out.flush()) {
      std::filesystem::remove(temporary, error);
      return false;
    }
  }
  std::filesystem::rename(temporary, file, error);
  if (!error) return true;
  std::filesystem::remove(temporary, error);
  return false;
}

}  // namespace vscan::physics

#include "store/data_quota.h"

#include <gtest/gtest.h>

#include <fstream>
#include <memory>

#include "store/blob_store.h"
#include "vscan_test/temp_dir.h"

namespace vscan::store {
namespace {

namespace fs = std::filesystem;

void WriteFile(const fs::path& path, size_t bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << std::string(bytes, 'x');
}

TEST(DataQuotaTest, BlobsAndCountedFilesShareTheBound) {
  test::TempDir dir;
  const fs::path journal = dir.path() / "catalogue.sqlite";
  WriteFile(journal, 300);
  BlobStore blobs(dir.path() / "blobs");
  ASSERT_TRUE(blobs.Open().ok());
  auto quota = std::make_shared<DataQuota>(1000, std::vector<fs::path>{journal, dir.path() / "absent"});
  ASSERT_TRUE(quota->CountExisting(dir.path() / "blobs").ok());
  blobs.UseQuota(quota);

  const std::string a(400, 'a'), b(400, 'b');
  auto first = blobs.Put(a);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  EXPECT_EQ(quota->used_bytes(), 700u);
  // 300 + 400 + 400 passes 1000: refused, and nothing is written.
  auto second = blobs.Put(b);
  ASSERT_EQ(second.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(second.status().message().find("--max-data-mib"), std::string::npos) << second.status().message();
  EXPECT_FALSE(blobs.Contains(Sha256Hex(b)));
  EXPECT_EQ(quota->used_bytes(), 700u);
  // The same bytes again take no room.
  EXPECT_TRUE(blobs.Put(a).ok());
  EXPECT_EQ(quota->used_bytes(), 700u);
  // Removing gives the room back; a smaller catalogue does too.
  ASSERT_TRUE(blobs.Remove(*first).ok());
  EXPECT_EQ(quota->used_bytes(), 300u);
  EXPECT_TRUE(blobs.Put(b).ok());
  WriteFile(journal, 0);
  EXPECT_EQ(quota->used_bytes(), 400u);
}

TEST(DataQuotaTest, CountsWhatADirectoryAlreadyHolds) {
  test::TempDir dir;
  {
    BlobStore blobs(dir.path() / "blobs");
    ASSERT_TRUE(blobs.Open().ok());
    ASSERT_TRUE(blobs.Put(std::string(250, 'a')).ok());
    ASSERT_TRUE(blobs.Put(std::string(150, 'b')).ok());
  }
  DataQuota quota(500, {});
  ASSERT_TRUE(quota.CountExisting(dir.path() / "blobs").ok());
  EXPECT_EQ(quota.used_bytes(), 400u);
  EXPECT_EQ(quota.Reserve(101).code(), StatusCode::kResourceExhausted);
  EXPECT_TRUE(quota.Reserve(100).ok());
  EXPECT_EQ(quota.Reserve(1).code(), StatusCode::kResourceExhausted);
  quota.Release(10);
  EXPECT_TRUE(quota.Reserve(10).ok());
  // A bound smaller than one write, and sizes near 2^64, never wrap.
  EXPECT_EQ(quota.Reserve(UINT64_MAX).code(), StatusCode::kResourceExhausted);
}

}  // namespace
}  // namespace vscan::store

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

TEST(DataQuotaTest, DirectoriesShareTheBoundAsLastMeasured) {
  DataQuota quota(1000, {});
  ASSERT_TRUE(quota.Reserve(200).ok());
  quota.SetDirectoryBytes("job_a", 300);
  quota.SetDirectoryBytes("job_b", 100);
  EXPECT_EQ(quota.used_bytes(), 600u);
  // A new measure replaces the old one rather than adding to it.
  quota.SetDirectoryBytes("job_a", 500);
  EXPECT_EQ(quota.used_bytes(), 800u);
  EXPECT_EQ(quota.DirectoryBytes("job_a"), 500u);
  // Blobs meet the directories' bytes: 800 + 201 passes 1000.
  EXPECT_EQ(quota.Reserve(201).code(), StatusCode::kResourceExhausted);
  EXPECT_TRUE(quota.CheckRoom(200, "the next scene").ok());
  const Status full = quota.CheckRoom(201, "the next scene");
  ASSERT_EQ(full.code(), StatusCode::kResourceExhausted);
  EXPECT_NE(full.message().find("the next scene"), std::string::npos) << full.message();
  EXPECT_NE(full.message().find("--max-data-mib"), std::string::npos) << full.message();
  // CheckRoom reserves nothing; leaving out a directory counts the others only (800 - 500 + 700).
  EXPECT_EQ(quota.used_bytes(), 800u);
  EXPECT_TRUE(quota.CheckRoom(700, "a resumed dataset", "job_a").ok());
  EXPECT_EQ(quota.CheckRoom(701, "a resumed dataset", "job_a").code(), StatusCode::kResourceExhausted);
  // Measured past the bound (the bytes are on disk already), it is counted all the same.
  quota.SetDirectoryBytes("job_b", 900);
  EXPECT_EQ(quota.used_bytes(), 1600u);
  quota.ForgetDirectory("job_b");
  quota.ForgetDirectory("job_unknown");
  EXPECT_EQ(quota.used_bytes(), 700u);
  EXPECT_EQ(quota.DirectoryBytes("job_b"), 0u);
}

TEST(DataQuotaTest, RegularFileBytesAddsEveryFileBelowARoot) {
  test::TempDir dir;
  fs::create_directories(dir.path() / "a" / "b");
  WriteFile(dir.path() / "top", 10);
  WriteFile(dir.path() / "a" / "one", 200);
  WriteFile(dir.path() / "a" / "b" / "two", 3000);
  std::error_code ec;
  EXPECT_EQ(RegularFileBytes(dir.path(), ec), 3210u);
  EXPECT_FALSE(ec);
  RegularFileBytes(dir.path() / "absent", ec);
  EXPECT_TRUE(ec);
}

}  // namespace
}  // namespace vscan::store

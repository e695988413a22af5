#include "store/blob_store.h"

#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "vscan_test/temp_dir.h"

namespace vscan::store {
namespace {

namespace fs = std::filesystem;

constexpr char kHelloSha[] = "2cf24dba5fb0a30e26e83b2ac5b9e29e1b161e5c1fa7425e73043362938b9824";

std::string RandomBytes(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string bytes(n, '\0');
  for (auto& c : bytes) c = static_cast<char>(rng() & 0xff);
  return bytes;
}

void Overwrite(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// Every entry must be a two-digit shard directory holding files named by a full hash with that prefix.
void ExpectOnlyBlobs(const fs::path& root) {
  for (const auto& shard : fs::directory_iterator(root)) {
    ASSERT_TRUE(shard.is_directory()) << shard.path();
    ASSERT_EQ(shard.path().filename().string().size(), 2u) << shard.path();
    for (const auto& file : fs::directory_iterator(shard)) {
      std::string name = file.path().filename().string();
      EXPECT_TRUE(file.is_regular_file()) << file.path();
      EXPECT_EQ(name.size(), 64u) << "leftover file " << file.path();
      EXPECT_EQ(name.substr(0, 2), shard.path().filename().string()) << file.path();
    }
  }
}

class BlobStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_FALSE(dir_.path().empty());
    ASSERT_TRUE(store_.Open().ok());
  }
  fs::path root() const { return dir_.path() / "blobs"; }

  test::TempDir dir_;
  BlobStore store_{dir_.path() / "blobs"};
};

TEST(Sha256HexTest, KnownVectors) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("hello"), kHelloSha);
}

TEST_F(BlobStoreTest, PutThenGetRoundTrips) {
  auto id = store_.Put("hello");
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  EXPECT_EQ(*id, kHelloSha);
  EXPECT_TRUE(fs::is_regular_file(root() / "2c" / kHelloSha));
  EXPECT_TRUE(store_.Contains(*id));

  auto bytes = store_.Get(*id);
  ASSERT_TRUE(bytes.ok()) << bytes.status().ToString();
  EXPECT_EQ(*bytes, "hello");
}

TEST_F(BlobStoreTest, LargeAndEmptyBlobsRoundTrip) {
  for (const std::string& data : {std::string(), RandomBytes(3 << 20, 7)}) {
    auto id = store_.Put(data);
    ASSERT_TRUE(id.ok()) << id.status().ToString();
    EXPECT_EQ(*id, Sha256Hex(data));
    auto back = store_.Get(*id);
    ASSERT_TRUE(back.ok()) << back.status().ToString();
    EXPECT_TRUE(*back == data);
  }
}

TEST_F(BlobStoreTest, PutIsIdempotent) {
  auto first = store_.Put("same bytes");
  auto second = store_.Put("same bytes");
  ASSERT_TRUE(first.ok() && second.ok());
  EXPECT_EQ(*first, *second);
  size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root())) files += entry.is_regular_file();
  EXPECT_EQ(files, 1u);
  ExpectOnlyBlobs(root());
}

TEST_F(BlobStoreTest, CorruptBlobIsDataLossAndPutRepairsIt) {
  auto id = store_.Put("precious");
  ASSERT_TRUE(id.ok());
  Overwrite(root() / id->substr(0, 2) / *id, "precioux");

  auto bytes = store_.Get(*id);
  ASSERT_FALSE(bytes.ok());
  EXPECT_EQ(bytes.status().code(), StatusCode::kDataLoss) << bytes.status().ToString();

  ASSERT_TRUE(store_.Put("precious").ok());
  auto repaired = store_.Get(*id);
  ASSERT_TRUE(repaired.ok()) << repaired.status().ToString();
  EXPECT_EQ(*repaired, "precious");
}

TEST_F(BlobStoreTest, TruncatedBlobIsDataLoss) {
  auto id = store_.Put(RandomBytes(1000, 3));
  ASSERT_TRUE(id.ok());
  fs::resize_file(root() / id->substr(0, 2) / *id, 999);
  EXPECT_EQ(store_.Get(*id).status().code(), StatusCode::kDataLoss);
}

TEST_F(BlobStoreTest, MissingBlobIsNotFound) {
  auto bytes = store_.Get(Sha256Hex("never stored"));
  ASSERT_FALSE(bytes.ok());
  EXPECT_EQ(bytes.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(bytes.status().message().rfind("sha256:", 0), 0u) << bytes.status().message();
  EXPECT_FALSE(store_.Contains(Sha256Hex("never stored")));
}

TEST_F(BlobStoreTest, ReaderReadsInChunksWhatGetReads) {
  const std::string data = RandomBytes((5 << 20) + 123, 11);
  auto id = store_.Put(data);
  ASSERT_TRUE(id.ok());
  auto reader = store_.OpenReader(*id);
  ASSERT_TRUE(reader.ok()) << reader.status().ToString();
  EXPECT_EQ(reader->size(), data.size());
  std::string joined;
  for (uint64_t offset = 0; offset < reader->size();) {
    auto chunk = reader->Read(offset, 1 << 20);
    ASSERT_TRUE(chunk.ok()) << chunk.status().ToString();
    ASSERT_LE(chunk->size(), size_t{1} << 20);
    ASSERT_FALSE(chunk->empty());
    offset += chunk->size();
    joined += *chunk;
  }
  EXPECT_TRUE(joined == data);
  EXPECT_EQ(reader->Read(reader->size(), 10).value(), "");
  // Removed while open: the open file still reads as verified.
  ASSERT_TRUE(store_.Remove(*id).ok());
  EXPECT_EQ(reader->Read(data.size() - 5, 100).value(), data.substr(data.size() - 5));
}

TEST_F(BlobStoreTest, ReaderChecksTheHashAndTheId) {
  auto id = store_.Put("precious");
  ASSERT_TRUE(id.ok());
  Overwrite(root() / id->substr(0, 2) / *id, "precioux");
  EXPECT_EQ(store_.OpenReader(*id).status().code(), StatusCode::kDataLoss);
  EXPECT_EQ(store_.OpenReader(Sha256Hex("never stored")).status().code(), StatusCode::kNotFound);
  EXPECT_EQ(store_.OpenReader("../etc/passwd").status().code(), StatusCode::kInvalidArgument);
}

TEST_F(BlobStoreTest, MalformedIdsAreInvalidArgument) {
  // Plant a file that a path trick could reach, to be sure it stays out of reach.
  Overwrite(dir_.path() / "secret", "secret");
  const std::string bad_ids[] = {
      "",
      "abc",
      std::string(kHelloSha).substr(0, 63),
      std::string(kHelloSha) + "0",
      "2CF24DBA5FB0A30E26E83B2AC5B9E29E1B161E5C1FA7425E73043362938B9824",
      "../secret",
      "2c/../../secret" + std::string(49, '0'),
      std::string(62, '0') + "/x",
      std::string(63, '0') + '\0',
  };
  for (const auto& id : bad_ids) {
    EXPECT_EQ(store_.Get(id).status().code(), StatusCode::kInvalidArgument) << id;
    EXPECT_EQ(store_.Remove(id).code(), StatusCode::kInvalidArgument) << id;
    EXPECT_FALSE(store_.Contains(id)) << id;
  }
  EXPECT_TRUE(fs::exists(dir_.path() / "secret"));
}

TEST_F(BlobStoreTest, RemoveDeletesAndIsIdempotent) {
  auto id = store_.Put("short-lived");
  ASSERT_TRUE(id.ok());
  EXPECT_TRUE(store_.Remove(*id).ok());
  EXPECT_FALSE(store_.Contains(*id));
  EXPECT_EQ(store_.Get(*id).status().code(), StatusCode::kNotFound);
  EXPECT_TRUE(store_.Remove(*id).ok());
}

TEST_F(BlobStoreTest, NoTempFilesLeftBehind) {
  for (unsigned i = 0; i < 20; ++i) ASSERT_TRUE(store_.Put(RandomBytes(1000 + i, i)).ok());
  ExpectOnlyBlobs(root());
}

TEST_F(BlobStoreTest, FailedPutLeavesNoTempFile) {
  // A directory squatting on the blob's final name makes the rename fail after the temp file is written.
  fs::create_directories(root() / "2c" / kHelloSha / "occupied");
  auto id = store_.Put("hello");
  ASSERT_FALSE(id.ok());
  EXPECT_TRUE(id.status().code() == StatusCode::kInternal || id.status().code() == StatusCode::kUnavailable)
      << id.status().ToString();
  for (const auto& entry : fs::directory_iterator(root() / "2c")) {
    EXPECT_EQ(entry.path().filename().string(), kHelloSha) << "leftover " << entry.path();
  }
}

TEST_F(BlobStoreTest, ShardPathBlockedByFileIsAnError) {
  Overwrite(root() / "2c", "not a directory");
  auto id = store_.Put("hello");
  ASSERT_FALSE(id.ok());
  EXPECT_NE(id.status().message().find(root().string()), std::string::npos) << id.status().message();
}

TEST(BlobStoreOpenTest, RootThatIsAFileIsUnavailable) {
  test::TempDir dir;
  Overwrite(dir.path() / "file", "x");
  BlobStore store(dir.path() / "file");
  EXPECT_EQ(store.Open().code(), StatusCode::kUnavailable);
}

}  // namespace
}  // namespace vscan::store

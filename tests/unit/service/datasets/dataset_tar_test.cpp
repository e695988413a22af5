// TarDirectory: ustar blocks of every regular file, sorted by path, and a stop between files.

#include "service/datasets/dataset_job_tar.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>

namespace vscan::service {
namespace {

class DatasetTarTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = std::filesystem::temp_directory_path() /
            ("vscan-tar-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(root_ / "scenes");
    std::ofstream(root_ / "b.json") << "{}";
    std::ofstream(root_ / "scenes" / "a.txt") << std::string(700, 'x');
  }
  void TearDown() override { std::filesystem::remove_all(root_); }
  std::filesystem::path root_;
};

TEST_F(DatasetTarTest, HoldsEveryFileInPathOrder) {
  auto tar = TarDirectory(root_, 1 << 20);
  ASSERT_TRUE(tar.ok()) << tar.status().ToString();
  // Two headers, 2 + 1024 bytes of data in whole blocks, two empty blocks at the end.
  EXPECT_EQ(tar->size(), 512u * (2 + 1 + 2 + 2));
  EXPECT_EQ(tar->substr(0, 6), "b.json");
  EXPECT_EQ(tar->substr(1024, 12), "scenes/a.txt");
  EXPECT_EQ(TarDirectory(root_, 100).status().code(), StatusCode::kFailedPrecondition);
}

TEST_F(DatasetTarTest, ACancelStopsIt) {
  std::atomic<bool> cancel{true};
  EXPECT_EQ(TarDirectory(root_, 1 << 20, &cancel).status().code(), StatusCode::kCancelled);
}

}  // namespace
}  // namespace vscan::service

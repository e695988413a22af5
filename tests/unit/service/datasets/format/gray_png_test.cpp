// 8-bit and 16-bit greyscale PNG: values come back as written, and the decoder refuses what it
// would have to convert.

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "vscan/common/png_codec.h"

namespace vscan {
namespace {

TEST(GrayPng, SixteenBitValuesComeBackExactly) {
  const uint32_t width = 7, height = 5;
  std::vector<uint16_t> values(width * height);
  for (size_t i = 0; i < values.size(); ++i) values[i] = static_cast<uint16_t>(i * 1873u + 1u);
  values[0] = 0;
  values[1] = 0x00ff;
  values[2] = 0xff00;
  values[3] = 0xffff;
  StatusOr<std::string> png = EncodeGray16Png(width, height, values);
  ASSERT_TRUE(png.ok()) << png.status().ToString();
  StatusOr<GrayPixels> decoded = DecodeGrayPng(*png);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_EQ(decoded->width, width);
  EXPECT_EQ(decoded->height, height);
  EXPECT_EQ(decoded->bit_depth, 16);
  EXPECT_EQ(decoded->values, values);
}

TEST(GrayPng, SixteenBitHeaderSaysGreyOfDepthSixteen) {
  const std::vector<uint16_t> values = {1, 2, 3, 4};
  StatusOr<std::string> png = EncodeGray16Png(2, 2, values);
  ASSERT_TRUE(png.ok());
  // IHDR follows the signature and the chunk's length and type: width, height, depth, colour type.
  ASSERT_GT(png->size(), 26u);
  EXPECT_EQ(png->substr(12, 4), "IHDR");
  EXPECT_EQ(static_cast<uint8_t>((*png)[24]), 16);
  EXPECT_EQ(static_cast<uint8_t>((*png)[25]), 0);
}

TEST(GrayPng, EightBitValuesComeBackWidened) {
  const std::vector<uint8_t> values = {0, 255, 128, 1, 7, 200};
  StatusOr<std::string> png = EncodeGray8Png(3, 2, values);
  ASSERT_TRUE(png.ok()) << png.status().ToString();
  StatusOr<GrayPixels> decoded = DecodeGrayPng(*png);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_EQ(decoded->bit_depth, 8);
  EXPECT_EQ(decoded->values, (std::vector<uint16_t>{0, 255, 128, 1, 7, 200}));
}

TEST(GrayPng, RgbIsRefusedNotConverted) {
  const std::vector<uint8_t> rgb(2 * 2 * 3, 9);
  StatusOr<std::string> png = EncodePng(2, 2, rgb);
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(DecodeGrayPng(*png).status().code(), StatusCode::kInvalidArgument);
}

TEST(GrayPng, TruncatedStreamIsDataLoss) {
  const std::vector<uint16_t> values(64 * 64, 4242);
  StatusOr<std::string> png = EncodeGray16Png(64, 64, values);
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(DecodeGrayPng(png->substr(0, png->size() / 2)).status().code(), StatusCode::kDataLoss);
}

TEST(GrayPng, WrongValueCountIsInvalidArgument) {
  const std::vector<uint16_t> values(5, 1);
  EXPECT_EQ(EncodeGray16Png(2, 2, values).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(EncodeGray8Png(0, 2, {}).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vscan

// Material messages: what is refused (naming the field) and what is stored for what is accepted.

#include "api/scenes/material_convert.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace vscan::api {
namespace {

v1::Material ValuesMessage(double albedo, double metallic, double roughness, double specular) {
  v1::Material material;
  material.mutable_values()->set_diffuse_albedo(albedo);
  material.mutable_values()->set_metallic(metallic);
  material.mutable_values()->set_roughness(roughness);
  material.mutable_values()->set_specular_reflectance(specular);
  return material;
}

void ExpectRefused(const v1::Material& material, const std::string& field_in_message) {
  const auto result = MaterialFromProto(material, "object.material");
  ASSERT_FALSE(result.ok()) << material.ShortDebugString();
  EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(result.status().message().rfind(field_in_message, 0), 0u)
      << "'" << result.status().message() << "' should start with " << field_in_message;
}

TEST(MaterialConvertTest, APresetIsStoredByName) {
  v1::Material material;
  material.set_preset("machined-aluminium");
  const auto record = MaterialFromProto(material, "material");
  ASSERT_TRUE(record.ok()) << record.status().ToString();
  EXPECT_EQ(record->preset, "machined-aluminium");
  v1::Material back;
  ToProto(*record, &back);
  EXPECT_EQ(back.preset(), "machined-aluminium");
  EXPECT_FALSE(back.has_values());
}

TEST(MaterialConvertTest, ValuesAreStoredAsGivenIncludingTheEdges) {
  const auto record = MaterialFromProto(ValuesMessage(0.0, 1.0, 1.0, 0.0), "material");
  ASSERT_TRUE(record.ok()) << record.status().ToString();
  EXPECT_EQ(*record, (store::MaterialRecord{"", 0.0, 1.0, 1.0, 0.0}));
  const auto smallest = MaterialFromProto(ValuesMessage(0.3, 0.0, 1e-9, 0.04), "material");
  ASSERT_TRUE(smallest.ok());
  v1::Material back;
  ToProto(*smallest, &back);
  EXPECT_TRUE(back.preset().empty());
  EXPECT_EQ(back.values().diffuse_albedo(), 0.3);
  EXPECT_EQ(back.values().roughness(), 1e-9);
  EXPECT_EQ(back.values().specular_reflectance(), 0.04);
}

TEST(MaterialConvertTest, AnUnknownPresetIsRefusedNamingTheFieldAndTheKnownOnes) {
  v1::Material material;
  material.set_preset("unobtainium");
  const auto result = MaterialFromProto(material, "object.material");
  ASSERT_EQ(result.status().code(), StatusCode::kInvalidArgument);
  const std::string& message = result.status().message();
  EXPECT_EQ(message.rfind("object.material.preset: unknown preset 'unobtainium'", 0), 0u) << message;
  EXPECT_NE(message.find("matte-grey"), std::string::npos) << message;
  EXPECT_NE(message.find("black-anodised-aluminium"), std::string::npos) << message;
  // Presets are matched exactly.
  material.set_preset("Machined-Aluminium");
  ExpectRefused(material, "object.material.preset");
  // A long or binary name is not echoed whole.
  material.set_preset(std::string(10000, 'x') + "\n");
  const auto long_name = MaterialFromProto(material, "m");
  ASSERT_FALSE(long_name.ok());
  EXPECT_LT(long_name.status().message().size(), 400u);
}

TEST(MaterialConvertTest, BadValuesAreRefusedNamingTheMember) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  ExpectRefused(ValuesMessage(nan, 0, 0.5, 0.04), "object.material.values.diffuse_albedo: NaN");
  ExpectRefused(ValuesMessage(0.5, 1e19, 0.5, 0.04), "object.material.values.metallic");
  ExpectRefused(ValuesMessage(0.5, 0, -inf, 0.04), "object.material.values.roughness: NaN or infinite");
  ExpectRefused(ValuesMessage(0.5, 0, 0.0, 0.04), "object.material.values.roughness");
  ExpectRefused(ValuesMessage(0.5, 0, 1.0000001, 0.04), "object.material.values.roughness");
  ExpectRefused(ValuesMessage(0.5, 0, 0.5, -0.01), "object.material.values.specular_reflectance");
  ExpectRefused(ValuesMessage(1.5, 0, 0.5, 0.04), "object.material.values.diffuse_albedo");
}

TEST(MaterialConvertTest, BothOrNeitherIsRefused) {
  v1::Material both = ValuesMessage(0.5, 0, 0.5, 0.04);
  both.set_preset("cardboard");
  ExpectRefused(both, "object.material: give a preset or values, not both");
  ExpectRefused(v1::Material{}, "object.material: give a preset or values");
}

TEST(MaterialConvertTest, AnAbsentMessageIsNoMaterial) {
  v1::Material ignored;
  ignored.set_preset("unobtainium");
  const auto absent = OptionalMaterialFromProto(false, ignored, "material");
  ASSERT_TRUE(absent.ok());
  EXPECT_FALSE(absent->has_value());
  EXPECT_FALSE(OptionalMaterialFromProto(true, ignored, "material").ok());
}

}  // namespace
}  // namespace vscan::api

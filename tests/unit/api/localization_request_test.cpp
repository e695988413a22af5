// LocalizeRequest's parts checked field by field: the single-part form, the list form, and every
// refusal naming the part's field.

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "api/localization/localization_request.h"

namespace vscan::api {
namespace {

constexpr const char* kBlock = "msh_00000000000000a1";
constexpr const char* kTube = "msh_00000000000000b2";

v1::LocalizeRequest WithPoints() {
  v1::LocalizeRequest request;
  const float xyz[3] = {0, 0, 0};
  request.mutable_points()->set_positions(std::string(reinterpret_cast<const char*>(xyz), sizeof(xyz)));
  return request;
}

v1::LocalizePart* AddPart(v1::LocalizeRequest& request, const std::string& mesh_id, double scale = 0,
                          uint32_t max_instances = 0) {
  v1::LocalizePart* part = request.add_parts();
  part->set_mesh_id(mesh_id);
  part->set_scale(scale);
  part->set_max_instances(max_instances);
  return part;
}

void ExpectRefused(const v1::LocalizeRequest& request, StatusCode code, const std::string& field) {
  const auto plan = ParseLocalizeRequest(request);
  ASSERT_FALSE(plan.ok()) << "accepted; expected a refusal naming " << field;
  EXPECT_EQ(plan.status().code(), code) << plan.status().ToString();
  EXPECT_EQ(plan.status().field(), field) << plan.status().message();
}

TEST(LocalizeRequestParts, TheSingleMeshIsOnePart) {
  v1::LocalizeRequest request = WithPoints();
  request.set_mesh_id(kBlock);
  request.set_scale(2.5);
  request.mutable_options()->set_max_instances(7);
  const auto plan = ParseLocalizeRequest(request);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_EQ(plan->parts.size(), 1u);
  EXPECT_EQ(plan->parts[0].mesh_id, kBlock);
  EXPECT_EQ(plan->parts[0].scale, 2.5);
  EXPECT_EQ(plan->parts[0].max_instances, 0u);  // the options' 7
  EXPECT_EQ(plan->parts[0].field, "mesh_id");
  EXPECT_EQ(plan->options.max_instances, 7u);
}

TEST(LocalizeRequestParts, ListedPartsKeepTheirOrderScaleAndCount) {
  v1::LocalizeRequest request = WithPoints();
  AddPart(request, kBlock, 0, 6);
  AddPart(request, kTube, 0.127, 0);
  AddPart(request, kBlock, 2, 1);  // the same mesh at another scale is another part
  const auto plan = ParseLocalizeRequest(request);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_EQ(plan->parts.size(), 3u);
  EXPECT_EQ(plan->parts[0].scale, 1.0);
  EXPECT_EQ(plan->parts[0].max_instances, 6u);
  EXPECT_EQ(plan->parts[1].mesh_id, kTube);
  EXPECT_EQ(plan->parts[1].scale, 0.127);
  EXPECT_EQ(plan->parts[1].max_instances, 0u);
  EXPECT_EQ(plan->parts[1].field, "parts[1].mesh_id");
  EXPECT_EQ(plan->parts[2].scale, 2.0);
}

TEST(LocalizeRequestParts, RefusesEachBadFieldByName) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double scale : {nan, -1.0, 1e19, inf, -0.0001}) {
    v1::LocalizeRequest request = WithPoints();
    AddPart(request, kBlock);
    AddPart(request, kTube, scale);
    SCOPED_TRACE(scale);
    ExpectRefused(request, StatusCode::kInvalidArgument, "parts[1].scale");
  }
  {
    v1::LocalizeRequest request = WithPoints();
    AddPart(request, kBlock, 0, 101);
    ExpectRefused(request, StatusCode::kInvalidArgument, "parts[0].max_instances");
  }
  {
    v1::LocalizeRequest request = WithPoints();
    AddPart(request, kBlock, 0, std::numeric_limits<uint32_t>::max());
    ExpectRefused(request, StatusCode::kInvalidArgument, "parts[0].max_instances");
  }
  const std::vector<std::string> bad_ids{"", "msh with spaces", std::string(65, 'a'), std::string("msh_\0x", 6)};
  for (const std::string& id : bad_ids) {
    v1::LocalizeRequest request = WithPoints();
    AddPart(request, kBlock);
    AddPart(request, id);
    ExpectRefused(request, StatusCode::kInvalidArgument, "parts[1].mesh_id");
  }
}

TEST(LocalizeRequestParts, RefusesMixedFormsRepeatsAndTooMuch) {
  {
    v1::LocalizeRequest request = WithPoints();
    request.set_mesh_id(kBlock);
    AddPart(request, kTube);
    ExpectRefused(request, StatusCode::kInvalidArgument, "parts");
  }
  {
    v1::LocalizeRequest request = WithPoints();
    request.set_scale(2);
    AddPart(request, kTube);
    ExpectRefused(request, StatusCode::kInvalidArgument, "scale");
  }
  {
    v1::LocalizeRequest request = WithPoints();  // neither form
    ExpectRefused(request, StatusCode::kInvalidArgument, "mesh_id");
  }
  {
    // Scale 0 is 1: the same part twice.
    v1::LocalizeRequest request = WithPoints();
    AddPart(request, kBlock, 1);
    AddPart(request, kTube);
    AddPart(request, kBlock, 0, 3);
    ExpectRefused(request, StatusCode::kInvalidArgument, "parts[2]");
  }
  {
    v1::LocalizeRequest request = WithPoints();
    for (int i = 0; i < 17; ++i) AddPart(request, "msh_" + std::to_string(1000000000000000 + i), 0, 1);
    ExpectRefused(request, StatusCode::kInvalidArgument, "parts");
    request.mutable_parts()->RemoveLast();
    EXPECT_TRUE(ParseLocalizeRequest(request).ok());
  }
  {
    // 16 parts at the options' default of 10 fit; at 13 each they add up past 200.
    v1::LocalizeRequest request = WithPoints();
    for (int i = 0; i < 16; ++i) AddPart(request, "msh_" + std::to_string(1000000000000000 + i));
    EXPECT_TRUE(ParseLocalizeRequest(request).ok());
    request.mutable_options()->set_max_instances(13);
    ExpectRefused(request, StatusCode::kInvalidArgument, "parts");
  }
}

TEST(LocalizeRequestParts, ChecksTheSourceAndOptionsBeforeTheParts) {
  v1::LocalizeRequest request;
  AddPart(request, kBlock, -1);
  ExpectRefused(request, StatusCode::kInvalidArgument, "source");
  request = WithPoints();
  AddPart(request, kBlock, -1);
  request.mutable_options()->set_min_score(std::nan(""));
  ExpectRefused(request, StatusCode::kInvalidArgument, "options.min_score");
}

}  // namespace
}  // namespace vscan::api

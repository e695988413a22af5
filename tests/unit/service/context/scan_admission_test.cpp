// Scan admission: a slot per running scan, RESOURCE_EXHAUSTED past the limit, freed on release.

#include <gtest/gtest.h>

#include <utility>

#include "service/context/scan_admission.h"

namespace vscan::service {
namespace {

TEST(ScanAdmissionTest, RefusesPastTheLimitAndAdmitsAgainOnceASlotIsFreed) {
  ScanAdmission admission(2);
  auto first = admission.Admit();
  auto second = admission.Admit();
  ASSERT_TRUE(first.ok());
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(admission.running(), 2u);

  const auto third = admission.Admit();
  ASSERT_FALSE(third.ok());
  EXPECT_EQ(third.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(third.status().message().find("2 scans already running"), std::string::npos) << third.status().message();
  EXPECT_EQ(admission.running(), 2u);  // a refusal holds nothing

  first->Release();
  EXPECT_EQ(admission.running(), 1u);
  EXPECT_TRUE(admission.Admit().ok());  // and the temporary slot is released at once
  EXPECT_EQ(admission.running(), 1u);
}

TEST(ScanAdmissionTest, ASlotIsReleasedOnceWhereverItMoves) {
  ScanAdmission admission(1);
  {
    ScanSlot held = std::move(admission.Admit()).value();
    ScanSlot moved = std::move(held);
    EXPECT_FALSE(held.held());
    EXPECT_TRUE(moved.held());
    EXPECT_FALSE(admission.Admit().ok());
    ScanSlot assigned;
    assigned = std::move(moved);
    EXPECT_EQ(admission.running(), 1u);
  }
  EXPECT_EQ(admission.running(), 0u);
  EXPECT_TRUE(admission.Admit().ok());
}

}  // namespace
}  // namespace vscan::service

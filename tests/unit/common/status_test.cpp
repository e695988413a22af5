#include "vscan/common/status.h"

#include <string>

#include <gtest/gtest.h>

namespace vscan {
namespace {

TEST(StatusTest, FieldTravelsAsDataAndLeadsTheMessage) {
  const Status s = InvalidArgument("mount_id", "no mount 'm1'");
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.field(), "mount_id");
  EXPECT_EQ(s.text(), "no mount 'm1'");
  EXPECT_EQ(s.message(), "mount_id: no mount 'm1'");
  EXPECT_EQ(s.ToString(), "INVALID_ARGUMENT: mount_id: no mount 'm1'");
}

TEST(StatusTest, PlainMessagesNameNoField) {
  const Status s = Internal("mount_id: looks like a field but is only text");
  EXPECT_TRUE(s.field().empty());
  EXPECT_EQ(s.text(), s.message());
  EXPECT_EQ(Status(StatusCode::kNotFound, "", "bare").message(), "bare");
}

TEST(StatusTest, FieldPrefixNestsThePath) {
  const Status nested = NotFound("mount_id", "no mount 'm1'").WithFieldPrefix("robot").WithFieldPrefix("spec");
  EXPECT_EQ(nested.code(), StatusCode::kNotFound);
  EXPECT_EQ(nested.field(), "spec.robot.mount_id");
  EXPECT_EQ(nested.text(), "no mount 'm1'");
  EXPECT_EQ(nested.message(), "spec.robot.mount_id: no mount 'm1'");
  // Without a field, the error is about the parent as a whole.
  const Status whole = OutOfRange("too far").WithFieldPrefix("tool_position");
  EXPECT_EQ(whole.field(), "tool_position");
  EXPECT_EQ(whole.message(), "tool_position: too far");
  EXPECT_TRUE(Status::Ok().WithFieldPrefix("robot").ok());
}

TEST(StatusTest, WithCodeKeepsTheField) {
  const Status s = NotFound("base_link", "no link 'x'").WithCode(StatusCode::kInvalidArgument);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.field(), "base_link");
  EXPECT_EQ(s.message(), "base_link: no link 'x'");
}

TEST(StatusOrDeathTest, ValueOfAnErrorAbortsWithTheMessage) {
  const StatusOr<int> error = NotFound("scene_id", "no scene 's9'");
  EXPECT_DEATH((void)error.value(), "NOT_FOUND: scene_id: no scene 's9'");
  EXPECT_DEATH((void)*error, "no scene 's9'");
  StatusOr<std::string> text = Internal("broken");
  EXPECT_DEATH((void)text->size(), "INTERNAL: broken");
  EXPECT_DEATH((void)std::move(text).value(), "broken");
}

TEST(StatusOrTest, AnOkStatusIsNotAValue) {
#ifdef NDEBUG
  const StatusOr<int> odd = Status::Ok();
  EXPECT_FALSE(odd.ok());
  EXPECT_EQ(odd.status().code(), StatusCode::kInternal);
#else
  GTEST_SKIP() << "asserts in debug builds";
#endif
}

}  // namespace
}  // namespace vscan

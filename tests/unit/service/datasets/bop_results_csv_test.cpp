// The BOP results file: good rows as bop_toolkit reads them, and bad rows refused naming the line
// and the column.

#include "service/datasets/format/bop_results_csv.h"

#include <gtest/gtest.h>

#include <string>

namespace vscan::service::dataset {
namespace {

constexpr const char* kIdentity = "1 0 0 0 1 0 0 0 1";

std::string Row(const std::string& ids, const std::string& score, const std::string& r, const std::string& t,
                const std::string& time = "-1") {
  return ids + "," + score + "," + r + "," + t + "," + time + "\n";
}

Status Refusal(const std::string& text) {
  const auto rows = ParseBopResultsCsv(text, "results_csv");
  EXPECT_FALSE(rows.ok());
  return rows.ok() ? Status::Ok() : rows.status();
}

TEST(BopResultsCsv, ReadsRowsWithAndWithoutHeader) {
  const std::string body = Row("3,0,2", "0.75", "0 -1 0 1 0 0 0 0 1", "10.5 -20 1.5e3", "0.25") +
                           "\r\n" + Row("3,1,1", "1", kIdentity, "0 0 400");
  for (const std::string& text : {body, "scene_id,im_id,obj_id,score,R,t,time\r\n" + body}) {
    const auto rows = ParseBopResultsCsv(text, "results_csv");
    ASSERT_TRUE(rows.ok()) << rows.status().ToString();
    ASSERT_EQ(rows->size(), 2u);
    const BopResultRow& first = (*rows)[0];
    EXPECT_EQ(first.scene_id, 3u);
    EXPECT_EQ(first.im_id, 0u);
    EXPECT_EQ(first.obj_id, 2u);
    EXPECT_EQ(first.score, 0.75);
    EXPECT_EQ(first.camera_R_model(0, 1), -1);  // row-major
    EXPECT_EQ(first.camera_R_model(1, 0), 1);
    EXPECT_EQ(first.camera_t_model_mm, Eigen::Vector3d(10.5, -20, 1500));
    EXPECT_EQ(first.time, 0.25);
    EXPECT_EQ((*rows)[1].line, first.line + 2);  // the blank line is counted, not read
  }
  const auto empty = ParseBopResultsCsv("scene_id,im_id,obj_id,score,R,t,time\n\n", "results_csv");
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty->empty());
}

TEST(BopResultsCsv, RefusesBadRowsNamingLineAndColumn) {
  const std::string good = Row("0,0,1", "1", kIdentity, "0 0 500");
  struct Case {
    std::string row;
    std::string says;
  };
  const Case cases[] = {
      {"0,0,1,1," + std::string(kIdentity) + ",0 0 500\n", "line 2: 6 comma-separated fields"},
      {Row("-1,0,1", "1", kIdentity, "0 0 500"), "line 2, column 1 (scene_id): '-1' is not a whole number"},
      {Row("0,1.5,1", "1", kIdentity, "0 0 500"), "line 2, column 2 (im_id)"},
      {Row("0,0,4294967296", "1", kIdentity, "0 0 500"), "line 2, column 3 (obj_id)"},
      {Row("0,0,1", "nan", kIdentity, "0 0 500"), "line 2, column 4 (score): 'nan' is not finite"},
      {Row("0,0,1", "", kIdentity, "0 0 500"), "line 2, column 4 (score): expected 1 number, found 0"},
      {Row("0,0,1", "1", "1 0 0 0 1 0 0 0", "0 0 500"), "line 2, column 5 (R): expected 9 numbers, found 8"},
      {Row("0,0,1", "1", "1 0 0 0 1 0 0 0 1 0", "0 0 500"), "line 2, column 5 (R): expected 9 numbers, found more"},
      {Row("0,0,1", "1", "2 0 0 0 1 0 0 0 1", "0 0 500"), "line 2, column 5 (R): not a rotation"},
      {Row("0,0,1", "1", "-1 0 0 0 1 0 0 0 1", "0 0 500"), "line 2, column 5 (R): not a rotation"},
      {Row("0,0,1", "1", "1e300 0 0 0 1e300 0 0 0 1", "0 0 500"), "line 2, column 5 (R): not a rotation"},
      {Row("0,0,1", "1", kIdentity, "0 0 1e19"), "line 2, column 6 (t): beyond 10000000 mm"},
      {Row("0,0,1", "1", kIdentity, "0 inf 5"), "line 2, column 6 (t): 'inf' is not finite"},
      {Row("0,0,1", "1", kIdentity, "0 0 5 ,"), "line 2: more than 7"},
      {Row("0,0,1", "1", kIdentity, "0 0 500", "NaN"), "line 2, column 7 (time)"},
      {Row("0,0,1", "1", kIdentity, "0 0 500", "1e999"), "line 2, column 7 (time)"},
  };
  for (const Case& c : cases) {
    const Status status = Refusal(good + c.row + good);
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << c.row;
    EXPECT_EQ(status.field(), "results_csv") << c.row;
    EXPECT_NE(status.message().find(c.says), std::string::npos) << c.row << " -> " << status.message();
  }
  // The header is taken as one only on the first line.
  EXPECT_NE(Refusal(good + "scene_id,im_id,obj_id,score,R,t,time\n").message().find("line 2, column 1"),
            std::string::npos);
  EXPECT_NE(Refusal(good + std::string("0,0,1\0,1,x,y,z\n", 15)).message().find("line 2: holds a NUL byte"),
            std::string::npos);
}

}  // namespace
}  // namespace vscan::service::dataset

#include "api/reports/report_convert.h"

namespace vscan::api {

void AddVector(const Eigen::Vector3d& v, google::protobuf::RepeatedField<double>* out) {
  out->Add(v.data(), v.data() + 3);
}

void AddMatrix(const Pose3& pose, google::protobuf::RepeatedField<double>* out) {
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) out->Add(pose.matrix()(r, c));
  }
}

void SetList(const Eigen::VectorXd& v, google::protobuf::ListValue* out) {
  out->Clear();
  for (Eigen::Index i = 0; i < v.size(); ++i) out->add_values()->set_number_value(v[i]);
}

void SetList(const Pose3& pose, google::protobuf::ListValue* out) {
  out->Clear();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) out->add_values()->set_number_value(pose.matrix()(r, c));
  }
}

}  // namespace vscan::api

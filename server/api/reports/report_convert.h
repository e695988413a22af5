#pragma once
// The reports jobs leave, from the service layer's structs into their messages in
// proto/vscan/v1/reports.proto: the one place their keys are decided.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <google/protobuf/repeated_field.h>
#include <google/protobuf/struct.pb.h>

#include "service/bins/bin_fill_report.h"
#include "service/campaign/campaign_summary.h"
#include "service/model/model_report.h"
#include "service/picking/picking_report.h"
#include "vscan/common/pose.h"
#include "vscan/v1/reports.pb.h"

namespace vscan::api {

v1::ModelReport ModelReportMessage(const service::ModelReport& report);
v1::CampaignReport CampaignReportMessage(const std::string& job_id, const std::string& final_state,
                                         const service::CampaignPlan& plan,
                                         const std::vector<service::CampaignStepRecord>& steps);
v1::BinReport BinReportMessage(const service::BinFillPlan& plan, const service::BinFillReport& report);
v1::PickingReport PickingReportMessage(const service::PickingPlan& plan, const service::PickingJobReport& report);
v1::PickingStepTruth PickingStepTruthMessage(const service::PickingPlan& plan, const service::StepView& view);

// Arrays as the reports hold them: [x, y, z], row-major 4x4.
void AddVector(const Eigen::Vector3d& v, google::protobuf::RepeatedField<double>* out);
void AddMatrix(const Pose3& pose, google::protobuf::RepeatedField<double>* out);
void SetList(const Eigen::VectorXd& v, google::protobuf::ListValue* out);
void SetList(const Pose3& pose, google::protobuf::ListValue* out);

}  // namespace vscan::api

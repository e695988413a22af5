#include "bins/bin_report.h"

#include <cstdio>

#include "model/model_fetch.h"
#include "session/text_format.h"
#include "vscan/common/report_json.h"

namespace vscan::cli {

int FetchBinReport(Context& ctx, const v1::Job& job, std::optional<v1::BinReport>* report) {
  std::optional<std::string> text;
  if (const int rc = FetchArtifactText(ctx, job, "bin.json", &text); rc != kExitOk || !text) return rc;
  v1::BinReport parsed;
  if (const Status status = ParseReport(*text, "bin.json", &parsed); !status.ok()) return ctx.ServerError(status);
  *report = std::move(parsed);
  return kExitOk;
}

std::string FormatBinReport(const v1::BinReport& report) {
  if (report.end().empty()) return "the fill did not run to an end: " + report.message() + "\n";
  const double in_bin = report.in_bin();
  std::string out = report.end() + ": " + Format("%.0f", in_bin) + " of " +
                    Format("%.0f", static_cast<double>(report.parts_asked())) + " parts in the bin, " +
                    Format("%.0f", report.spawned() - in_bin) + " fell out; " +
                    Format("%.2f", report.simulated_s()) + " s simulated in " +
                    Format("%.0f", static_cast<double>(report.steps())) + " steps (" + report.end_message() + ")\n";
  out += "deepest overlap: part-part " + Format("%.2f", report.max_part_part_penetration_m() * 1e3) +
         " mm, part-bin " + Format("%.2f", report.max_part_bin_penetration_m() * 1e3) + " mm; wall time " +
         Format("%.2f", report.setup_wall_s() + report.step_wall_s()) + " s\n";
  if (report.applied()) {
    out += "scene " + report.scene_id() + " revision " + Format("%.0f", report.scene_revision()) +
           ": the bin and its parts are objects of the scene\n";
  } else {
    out += "scene " + report.scene_id() + " unchanged\n";
  }
  if (report.has_picks()) {
    const v1::BinReportPicks& picks = report.picks();
    out += Format("%.0f", static_cast<double>(picks.pickable())) + " of " +
           Format("%.0f", static_cast<double>(picks.parts_checked())) + " parts pickable by mount " +
           picks.mount_id() + " (" + picks.gripper() + "; checked in " + Format("%.2f", picks.elapsed_s()) + " s)\n";
  }
  return out;
}

}  // namespace vscan::cli

#pragma once
// Saves a job's artifacts, and the job itself as job.json, into a directory.

#include <string>
#include <vector>

#include "session/context.h"

namespace vscan::cli {

// Creates dir if needed; returns an exit code (5 for local write errors) and fills *files with the
// paths written.
int DownloadArtifacts(Context& ctx, const v1::Job& job, const std::string& dir, std::vector<std::string>* files);

}  // namespace vscan::cli

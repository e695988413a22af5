#pragma once
// The commands every kind of job shares (`vscan campaign ...`, `vscan model ...`): list, cancel,
// delete, artifacts. help is the command's one-line description.

#include <string>
#include <vector>

#include "session/commands.h"

namespace vscan::cli {

// Lists the jobs of one kind ("campaign", "model"), newest first.
void AddJobList(CLI::App& group, Context& ctx, const std::string& kind, const std::string& help);
void AddJobCancel(CLI::App& group, Context& ctx, const std::string& help);
void AddJobDelete(CLI::App& group, Context& ctx, const std::string& help);
void AddJobArtifacts(CLI::App& group, Context& ctx);

// A JSON array of strings.
std::string JsonStrings(const std::vector<std::string>& items);

}  // namespace vscan::cli

#pragma once
// What every command shares: global options, the client, output in text or JSON, exit codes.

#include <functional>
#include <optional>
#include <string>

#include <google/protobuf/message.h>

#include "vscan/common/json_quote.h"
#include "vscan/client/client.h"
#include "vscan/common/status.h"

namespace vscan::cli {

enum ExitCode : int {
  kExitOk = 0,
  kExitUsage = 2,
  kExitServerError = 3,
  kExitUnreachable = 4,
  kExitLocalIo = 5,
};

struct GlobalOptions {
  std::string server = "127.0.0.1:50051";
  std::string token;
  std::string ca_cert;
  std::string client_cert;
  std::string client_key;
  bool tls = false;
  bool json = false;
  bool quiet = false;
  // Seconds; when given it also bounds streaming calls.
  std::optional<double> timeout;
};

class Context {
 public:
  GlobalOptions global;
  // Set by the chosen subcommand during parsing, run afterwards.
  std::function<int()> action;

  // Connects lazily; nullptr after printing the error (see last_exit()).
  client::Client* GetClient();
  int last_exit() const { return last_exit_; }

  bool json() const { return global.json; }
  bool quiet() const { return global.quiet; }
  // Every line is flushed as it is written, so that a pipe sees it at once.
  // Human-readable line on stdout unless --json or --quiet.
  void Say(const std::string& line) const;
  // Printed even with --quiet (ids for scripts), never with --json.
  void Print(const std::string& line) const;
  // The outcome of a command that created or changed something: line normally, id with --quiet.
  void Done(const std::string& line, const std::string& id) const;
  // One JSON object on stdout (a job's events come before it, one JSON object a line).
  void EmitJson(const std::string& json_object) const;

  // Error from a server call: exit 3, or 4 when the server could not be reached.
  int ServerError(const Status& status) const;
  // Error reading or writing local files: exit 5.
  int LocalError(const Status& status) const;
  // Bad arguments found after parsing: exit 2.
  int UsageError(const std::string& message) const;

 private:
  int Report(const Status& status, int exit_code) const;

  std::optional<client::Client> client_;
  int last_exit_ = kExitOk;
};

// Canonical proto3 JSON (lowerCamelCase names, zero values included) on one line.
std::string ToJson(const google::protobuf::Message& message);

}  // namespace vscan::cli

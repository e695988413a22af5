#include "session/commands.h"

namespace vscan::cli {

void AddHealthCommand(CLI::App& app, Context& ctx) {
  auto* cmd = app.add_subcommand("health", "Ask the server whether it is serving (exit 0 only when it is)");
  auto service = std::make_shared<std::string>();
  cmd->add_option("--service", *service, "Service name to ask about (default: the whole server)");
  OnRun(cmd, ctx, [&ctx, service]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto response = client->Health(*service);
    if (!response.ok()) return ctx.ServerError(response.status());
    if (ctx.json()) {
      ctx.EmitJson(ToJson(*response));
    } else {
      ctx.Print(grpc::health::v1::HealthCheckResponse::ServingStatus_Name(response->status()));
    }
    return response->status() == grpc::health::v1::HealthCheckResponse::SERVING ? kExitOk : kExitServerError;
  });
}

}  // namespace vscan::cli

// vscan-load: concurrent clients against a local vscand, with latency and server memory.

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>

#include "campaign/campaign_setup.h"
#include "load_address.h"
#include "load_report.h"
#include "memory_sampler.h"
#include "process_memory.h"
#include "session/app_main.h"

namespace vscan::cli {
namespace {

constexpr auto kMemoryPeriod = std::chrono::milliseconds(50);
constexpr auto kConnectWait = std::chrono::seconds(10);
// A scan that has not finished in this long counts as failed (DEADLINE_EXCEEDED).
constexpr auto kScanDeadline = std::chrono::milliseconds(120000);

struct LoadArgs {
  std::string plan;
  int clients = 1;
  double duration_s = 30;
  std::optional<uint64_t> requests;
  std::string mix = "scan=1,ik=1,catalogue=1";
  uint32_t width = 1280;
  uint32_t height = 1024;
  uint64_t seed = 1;
  std::optional<pid_t> server_pid;
};

// "scan=2,ik=1,catalogue=1": relative weights; kinds left out weigh 0.
StatusOr<std::array<double, kLoadKinds>> ParseMix(const std::string& text) {
  std::array<double, kLoadKinds> weights{0, 0, 0};
  std::istringstream items(text);
  for (std::string item; std::getline(items, item, ',');) {
    const size_t equals = item.find('=');
    const std::string name = item.substr(0, equals);
    size_t kind = kLoadKinds;
    for (size_t k = 0; k < kLoadKinds; ++k) {
      if (name == LoadKindName(static_cast<LoadKind>(k))) kind = k;
    }
    if (kind == kLoadKinds || equals == std::string::npos) {
      return InvalidArgument("--mix: expected scan=W,ik=W,catalogue=W, got '" + item + "'");
    }
    std::istringstream number(item.substr(equals + 1));
    double weight = -1;
    if (!(number >> weight) || !number.eof() || !(weight >= 0 && weight <= 1e6)) {
      return InvalidArgument("--mix: " + name + ": weight must be a number in [0, 1e6]");
    }
    weights[kind] = weight;
  }
  if (weights[0] + weights[1] + weights[2] <= 0) return InvalidArgument("--mix: at least one weight must be positive");
  return weights;
}

StatusOr<std::shared_ptr<grpc::ChannelCredentials>> Credentials(const std::string& ca_cert) {
  if (ca_cert.empty()) return grpc::InsecureChannelCredentials();
  std::ifstream in(ca_cert, std::ios::binary);
  std::ostringstream pem;
  if (!(pem << in.rdbuf())) return NotFound(ca_cert + ": cannot read the root certificate");
  grpc::SslCredentialsOptions options;
  options.pem_root_certs = pem.str();
  return grpc::SslCredentials(options);
}

// One channel per client: a local subchannel pool keeps gRPC from sharing one connection among them.
client::Client MakeClient(const Context& ctx, const std::shared_ptr<grpc::ChannelCredentials>& credentials) {
  client::ClientOptions options;
  options.bearer_token = ctx.global.token;
  options.stream_timeout = kScanDeadline;
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(options.max_receive_bytes);
  args.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
  args.SetInt(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, options.stream_window_bytes);
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  auto channel = grpc::CreateCustomChannel(ctx.global.server, credentials, args);
  // Connection set-up is not part of any call's latency.
  channel->WaitForConnected(std::chrono::system_clock::now() + kConnectWait);
  return client::Client(std::move(channel), std::move(options));
}

int RunLoadBench(Context& ctx, const LoadArgs& args) {
  const auto port = LoopbackPort(ctx.global.server);
  if (!port) {
    return ctx.UsageError("--server: vscan-load drives only a server on this machine (localhost, 127.0.0.0/8, "
                          "[::1] or unix:), not '" + ctx.global.server + "'");
  }
  const auto weights = ParseMix(args.mix);
  if (!weights.ok()) return ctx.UsageError(weights.status().message());
  const auto credentials = Credentials(ctx.global.ca_cert);
  if (!credentials.ok()) return ctx.LocalError(credentials.status());
  const auto plan = LoadCampaignPlan(args.plan);
  if (!plan.ok()) {
    if (plan.status().code() == StatusCode::kInvalidArgument) return ctx.UsageError(plan.status().message());
    return ctx.LocalError(plan.status());
  }
  if (plan->spec.viewpoints().empty() || (!plan->robot && plan->mount_id.empty())) {
    return ctx.UsageError(args.plan + ": vscan-load needs a plan with viewpoints and a robot (or mount_id)");
  }

  CampaignSetup setup;
  if (const int rc = SetUpCampaign(ctx, *plan, &setup); rc != kExitOk) {
    UndoCampaignSetup(ctx, setup);
    return rc;
  }
  LoadWork work;
  work.scene_id = setup.scene_id;
  work.mount_id = setup.mount_id;
  work.viewpoints.assign(plan->spec.viewpoints().begin(), plan->spec.viewpoints().end());
  work.width = args.width;
  work.height = args.height;
  work.noise = plan->spec.noise();

  LoadReport report;
  report.limits.clients = args.clients;
  report.limits.duration = std::chrono::duration<double>(args.duration_s);
  report.limits.requests = args.requests;
  report.limits.weights = *weights;
  report.limits.seed = args.seed;
  report.width = args.width;
  report.height = args.height;
  report.server_pid = args.server_pid;
  if (!report.server_pid && *port != 0) report.server_pid = FindListeningProcess(*port);

  ctx.Say("running " + std::to_string(args.clients) + " clients against " + ctx.global.server + "...");
  std::optional<MemorySampler> sampler;
  if (report.server_pid) sampler.emplace(*report.server_pid, kMemoryPeriod);
  report.run = RunLoad(work, report.limits, [&] { return MakeClient(ctx, *credentials); });
  if (sampler) report.memory = sampler->Stop();
  UndoCampaignSetup(ctx, setup);

  if (ctx.json()) {
    ctx.EmitJson(FormatLoadReportJson(report));
  } else {
    std::cout << FormatLoadReportText(report);
  }
  const bool none_ok = std::all_of(report.run.tally.ok_ms.begin(), report.run.tally.ok_ms.end(),
                                   [](const auto& samples) { return samples.empty(); });
  return none_ok ? kExitServerError : kExitOk;
}

// The load options on app itself: vscan-load has no subcommands.
void AddLoadOptions(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<LoadArgs>();
  app.add_option("PLAN", args->plan, "Campaign plan YAML: its scene, robot, viewpoints and noise")->required();
  app.add_option("--clients", args->clients, "Concurrent clients, each with its own channel")
      ->capture_default_str()->check(CLI::Range(1, 64));
  app.add_option("--duration", args->duration_s, "Seconds after which no call starts")
      ->capture_default_str()->check(CLI::Range(0.1, 600.0));
  app.add_option("--requests", args->requests, "Stop after this many calls in all (sooner than --duration)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1000000}));
  app.add_option("--mix", args->mix, "Relative weights of the calls")->capture_default_str();
  app.add_option("--width", args->width, "Scan width in pixels")->capture_default_str()->check(CLI::Range(1, 8192));
  app.add_option("--height", args->height, "Scan height in pixels")->capture_default_str()->check(CLI::Range(1, 8192));
  app.add_option("--seed", args->seed, "Seeds each client's draws (client i uses seed + i)")->capture_default_str();
  app.add_option("--server-pid", args->server_pid,
                 "The server's process id, for its memory (default: the process listening on --server's port)")
      ->check(CLI::Range(1, 1 << 22));
  OnRun(&app, ctx, [&ctx, args] { return RunLoadBench(ctx, *args); });
}

}  // namespace
}  // namespace vscan::cli

int main(int argc, char** argv) {
  vscan::cli::Context ctx;
  CLI::App app{"vscan-load: concurrent clients calling scans, inverse kinematics and catalogue reads against a local "
               "vscand, in the scene and with the robot of a campaign plan (created, then removed); reports "
               "throughput, latency and server memory", "vscan-load"};
  app.set_version_flag("--version", VSCAN_VERSION);
  vscan::cli::AddGlobalOptions(app, ctx.global);
  vscan::cli::AddLoadOptions(app, ctx);
  return vscan::cli::ParseAndRun(app, ctx, argc, argv);
}

// What a user of a separate vscand sees: a real vscand process on loopback, the ~160k-triangle
// bunny grid at 1280x1024, and single scans after an idle pause.
//  - one-shot: `vscan scan` as a new process (new channel), the cloud written to a file;
//  - after idle: this process on one open channel, a scan after an idle pause, then one at once
//    (warm), each timed here beside the server's reported total;
// each against a streaming vscand and a --whole-cloud-scans one, with the plain Embree packet loop
// over the same frame in this process as the limit. Rounds interleave the cases so that the
// machine's drift touches all of them.
//
//   oneshot_scan_bench [--runs N] [--idle-ms MS] [--output-dir DIR] [--vscand PATH] [--vscan PATH]
//   oneshot_scan_bench --hold SECONDS   (serve the scene and print the commands, to look by hand)

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <pthread.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include "bench_meshes.h"
#include "cli_scan.h"
#include "grid_scene_upload.h"
#include "packet_loop.h"
#include "raycast/embree_scene.h"
#include "raycast/raycast_scene.h"
#include "run_table.h"
#include "vscan/client/client.h"
#include "vscand_process.h"

namespace vscan::bench {
namespace {

using Clock = std::chrono::steady_clock;

const std::string kBunnyPath = std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply";

struct Options {
  int runs = 7;
  int idle_ms = 1000;
  std::string output_dir = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
  std::string vscand = VSCAN_VSCAND;
  std::string vscan = VSCAN_CLI;
  // Only start the servers, print the one-shot commands, and keep serving this long.
  int hold_s = 0;
};

[[noreturn]] void Usage(const char* why) {
  std::fprintf(stderr,
               "%s\nusage: oneshot_scan_bench [--runs N] [--idle-ms MS] [--output-dir DIR] [--vscand PATH] "
               "[--vscan PATH] [--hold SECONDS]\n",
               why);
  std::exit(2);
}

Options Parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) Usage(("missing value for " + flag).c_str());
    const std::string value = argv[++i];
    if (flag == "--runs") o.runs = std::max(1, std::atoi(value.c_str()));
    else if (flag == "--idle-ms") o.idle_ms = std::max(0, std::atoi(value.c_str()));
    else if (flag == "--output-dir") o.output_dir = value;
    else if (flag == "--vscand") o.vscand = value;
    else if (flag == "--vscan") o.vscan = value;
    else if (flag == "--hold") o.hold_s = std::max(0, std::atoi(value.c_str()));
    else Usage(("unknown flag " + flag).c_str());
  }
  return o;
}

void Check(const Status& status) {
  if (!status.ok()) throw std::runtime_error(status.ToString());
}

// A vscand process, this process's channel to it, and the scene's request.
struct Served {
  std::string label;
  std::unique_ptr<VscandProcess> process;
  std::unique_ptr<client::Client> client;
  v1::ScanRequest request;
};

std::unique_ptr<Served> Serve(const Options& o, const BunnyGrid& grid, bool whole_cloud) {
  auto s = std::make_unique<Served>();
  s->label = whole_cloud ? "whole cloud" : "streamed";
  s->process = std::make_unique<VscandProcess>(
      o.vscand, whole_cloud ? std::vector<std::string>{"--whole-cloud-scans"} : std::vector<std::string>{});
  auto connected = client::Client::Connect(s->process->address());
  Check(connected.status());
  s->client = std::make_unique<client::Client>(std::move(connected).value());
  auto request = UploadBunnyGrid(*s->client, grid, kBunnyPath, "oneshot-bench");
  Check(request.status());
  s->request = std::move(request).value();
  Check(s->client->Scan(s->request).status());  // builds the server's scene once
  return s;
}

CliScan OneShot(const Options& o, const Served& served, bool all_fields) {
  return {o.vscan, served.process->address(),
          o.output_dir + "/vscan-oneshot-bench-" + std::to_string(::getpid()) + ".ply",
          all_fields ? "all" : "position"};
}

void Hold(const Options& o, const BunnyGrid& grid, const Served& streamed, const Served& whole) {
  for (const Served* served : {&streamed, &whole}) {
    std::printf("%s:", served->label.c_str());
    for (const std::string& arg : CliScanArgv(OneShot(o, *served, false), served->request, grid.world_from_sensor)) {
      std::printf(" %s", arg.c_str());
    }
    std::printf("\n");
  }
  std::fflush(stdout);
  // Until the time is up or SIGINT/SIGTERM, then back to the caller, which stops the servers.
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  const timespec limit{o.hold_s, 0};
  sigtimedwait(&stop, nullptr, &limit);
}

v1::ScanRequest WithFields(v1::ScanRequest request, bool all_fields) {
  const int last = all_fields ? v1::POINT_FIELD_PIXEL : v1::POINT_FIELD_POSITION;
  for (int field = v1::POINT_FIELD_POSITION; field <= last; ++field) {
    request.add_fields(static_cast<v1::PointField>(field));
  }
  return request;
}

double ProcessCpuMs() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return (u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e3;
}

// This process does nothing else while it scans, so its CPU time is the client's.
RunFigures LibraryScan(client::Client& client, const v1::ScanRequest& request) {
  const double cpu_start = ProcessCpuMs();
  const auto start = Clock::now();
  Clock::time_point first{};
  client::ScanCallbacks callbacks;
  callbacks.on_progress = [&](uint64_t, uint64_t) {
    if (first == Clock::time_point{}) first = Clock::now();
  };
  auto result = client.Scan(request, callbacks);
  const auto end = Clock::now();
  Check(result.status());
  const auto ms = [&](Clock::time_point t) { return std::chrono::duration<double, std::milli>(t - start).count(); };
  RunFigures figures;
  figures.ms = ms(end);
  figures.points = static_cast<double>(result->cloud.size());
  figures.server_ms = result->stats.total_ms();
  figures.first_ms = ms(first);
  figures.cpu_ms = ProcessCpuMs() - cpu_start;
  return figures;
}

// The pause before a single request: idle_ms plus up to 100 ms, drawn from a fixed seed, so that
// runs sample the server's idle timers at every phase instead of one.
void Idle(const Options& o) {
  static std::mt19937 draw(20261124);
  std::uniform_int_distribution<int> extra(0, 99);
  std::this_thread::sleep_for(std::chrono::milliseconds(o.idle_ms + extra(draw)));
}

void Round(const Options& o, const BunnyGrid& grid, Served& served, bool all_fields, RunTable& table) {
  const std::string what = served.label + (all_fields ? ", all fields" : ", positions");
  const v1::ScanRequest request = WithFields(served.request, all_fields);
  const CliScan cli = OneShot(o, served, all_fields);
  Idle(o);
  table.Add("one-shot CLI, " + what, RunCliScan(cli, request, grid.world_from_sensor, o.output_dir));
  Idle(o);
  table.Add("after idle, " + what, LibraryScan(*served.client, request));
  table.Add("warm, " + what, LibraryScan(*served.client, request));
}

int Main(int argc, char** argv) {
  const Options o = Parse(argc, argv);
  const BunnyGrid grid = MakeBunnyGrid(ReadAsciiPly(kBunnyPath), 10, 1280, 1024);
  auto built = raycast::RaycastScene::Build(grid.instances);
  Check(built.status());
  const PacketLoop packets(vscan::raycast::EmbreeOf(**built).scene, grid.camera, grid.world_from_sensor);
  const auto streamed = Serve(o, grid, false);
  const auto whole = Serve(o, grid, true);
  if (o.hold_s > 0) {
    Hold(o, grid, *streamed, *whole);
    return 0;
  }
  std::printf("%d runs, %d-%d ms idle before each one-shot and after-idle scan; CLI output to %s\n", o.runs,
              o.idle_ms, o.idle_ms + 99, o.output_dir.c_str());
  RunTable table;
  packets.Frame();
  for (int run = 0; run < o.runs; ++run) {
    for (Served* served : {streamed.get(), whole.get()}) {
      for (const bool all_fields : {false, true}) Round(o, grid, *served, all_fields, table);
    }
    for (int frame = 0; frame < 3; ++frame) {
      const auto start = Clock::now();
      const uint64_t hits = packets.Frame();
      table.Add("plain Embree packet loop", {std::chrono::duration<double, std::milli>(Clock::now() - start).count(),
                                             static_cast<double>(hits)});
    }
    std::fprintf(stderr, "run %d of %d done\n", run + 1, o.runs);
  }
  table.Print("plain Embree packet loop");
  return 0;
}

}  // namespace
}  // namespace vscan::bench

int main(int argc, char** argv) {
  try {
    return vscan::bench::Main(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "oneshot_scan_bench: %s\n", e.what());
    return 1;
  }
}

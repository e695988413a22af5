// Reading point-cloud files: vscan's readers (ReadCloud, the code behind uploads) against PCL 1.13's
// loadPCDFile / loadPLYFile into a PCLPointCloud2, on the same files PCL wrote in each encoding: a
// VGA range image (640 x 480 = 307,200 points) of pcl::PointXYZINormal, from the page cache.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <unistd.h>

#include "vscan/common/cloud_io.h"

namespace vscan::bench {
namespace {

const char* const kFiles[] = {"binary.pcd", "ascii.pcd", "compressed.pcd", "binary.ply", "ascii.ply"};

// Writes the five files once into a scratch directory.
// Never destroyed, so that the exit handler that removes the directory can still name it.
const std::string& Directory() {
  static const std::string& dir = *new std::string([] {
    // PCL's PLY reader warns about every camera property it skips, on every read.
    pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
    const std::string d = (std::filesystem::temp_directory_path() / ("vscan_cloud_parse_" + std::to_string(::getpid())))
                              .string();
    std::filesystem::create_directories(d);
    pcl::PointCloud<pcl::PointXYZINormal> cloud(640, 480);
    for (uint32_t v = 0; v < 480; ++v) {
      for (uint32_t u = 0; u < 640; ++u) {
        pcl::PointXYZINormal& p = cloud.at(u, v);
        const float x = (static_cast<float>(u) - 320.0f) / 600.0f, y = (static_cast<float>(v) - 240.0f) / 600.0f;
        const float depth = 1.0f + 0.04f * std::sin(9.0f * x) * std::cos(7.0f * y) + 0.3f * x;
        p.x = depth * x;
        p.y = depth * y;
        p.z = depth;
        p.intensity = 1.0f / (depth * depth);
        p.normal_x = -0.3f;
        p.normal_y = 0.01f * y;
        p.normal_z = -1.0f;
        p.curvature = 0.0f;
      }
    }
    pcl::PCDWriter pcd;
    pcl::PLYWriter ply;
    const bool ok = pcd.writeBinary(d + "/binary.pcd", cloud) == 0 && pcd.writeASCII(d + "/ascii.pcd", cloud) == 0 &&
                    pcd.writeBinaryCompressed(d + "/compressed.pcd", cloud) == 0 &&
                    ply.write(d + "/binary.ply", cloud, true) == 0 && ply.write(d + "/ascii.ply", cloud, false) == 0;
    if (!ok) {
      std::fprintf(stderr, "cloud_parse_bench: cannot write the files in %s\n", d.c_str());
      std::exit(1);
    }
    std::atexit([] { std::filesystem::remove_all(Directory()); });
    return d;
  }());
  return dir;
}

void BM_Vscan(benchmark::State& state) {
  const std::string path = Directory() + "/" + kFiles[state.range(0)];
  state.SetLabel(kFiles[state.range(0)]);
  for (auto _ : state) {
    auto cloud = ReadCloud(path);
    if (!cloud.ok() || cloud->size() != 640 * 480) {
      state.SkipWithError(cloud.ok() ? "wrong point count" : cloud.status().ToString().c_str());
      return;
    }
    benchmark::DoNotOptimize(cloud->positions.data());
  }
}

void BM_Pcl(benchmark::State& state) {
  const std::string name = kFiles[state.range(0)];
  const std::string path = Directory() + "/" + name;
  state.SetLabel(name);
  for (auto _ : state) {
    pcl::PCLPointCloud2 cloud;
    const int rc = name.ends_with(".pcd") ? pcl::io::loadPCDFile(path, cloud) : pcl::io::loadPLYFile(path, cloud);
    if (rc != 0 || size_t{cloud.width} * cloud.height != 640 * 480) {
      state.SkipWithError("PCL could not read the file");
      return;
    }
    benchmark::DoNotOptimize(cloud.data.data());
  }
}

BENCHMARK(BM_Vscan)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Pcl)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vscan::bench

BENCHMARK_MAIN();

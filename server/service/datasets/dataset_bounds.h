#pragma once
// What a dataset plan asks of the server before it runs: how many images it makes, about how many
// bytes its directory and tar take on disk, and the server's bounds on both (--max-dataset-scenes,
// --max-data-mib).

#include <cstdint>

#include "service/datasets/dataset_job_setup.h"
#include "vscan/common/status.h"

namespace vscan::service {

// Datasets up to this size also become one artifact (dataset.tar); larger ones stay in the data
// directory only.
inline constexpr uint64_t kMaxTarArtifactBytes = 1ull << 30;
// The tar is built in memory, so it is also bounded by what one request may hold (0: no bound).
uint64_t DatasetTarBound(uint64_t max_request_memory_bytes);

// A scene's cloud takes 28 bytes per pixel (x y z, normal, instance) when every pixel is measured,
// as the table behind the bin makes it; the grey and reason images up to 3 more (noisy grey barely
// compresses), the other PNGs and JSON a few more.
inline constexpr uint64_t kDatasetBytesPerPixel = 31;

// Camera views of one scene (the plan's views.count).
uint64_t DatasetViewsPerScene(const dataset::DatasetPlan& plan);
// Images the plan writes: scenes x views.
uint64_t DatasetImageCount(const dataset::DatasetPlan& plan);

struct DatasetBytes {
  uint64_t directory = 0;  // scenes and models
  uint64_t tar = 0;        // the dataset.tar artifact, when the directory is small enough for one
  uint64_t total() const { return directory + tar; }
};

// One view of a sensor of width x height pixels.
uint64_t DatasetImageBytes(uint64_t width, uint64_t height);
// Every image at its sensor's resolution, plus each part's model mesh, plus the tar.
DatasetBytes EstimateDatasetBytes(const DatasetSetup& setup, uint64_t max_tar_bytes = kMaxTarArtifactBytes);

// RESOURCE_EXHAUSTED naming "seeds" and the flag when the plan makes more than max_scenes scenes.
Status CheckDatasetScenes(const dataset::DatasetPlan& plan, uint64_t max_scenes);

}  // namespace vscan::service

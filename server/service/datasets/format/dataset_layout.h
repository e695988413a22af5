#pragma once
// Where things live under a dataset root (docs/DATASETS.md, "Layout").

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace vscan::service::dataset {

// Bumped whenever a file or field changes meaning.
inline constexpr uint64_t kLayoutVersion = 2;

inline constexpr const char* kManifestFile = "dataset.json";
inline constexpr const char* kSceneIndexFile = "scenes.json";
inline constexpr const char* kModelsDir = "models";
inline constexpr const char* kModelsInfoFile = "models/models_info.json";
inline constexpr const char* kScenesDir = "train_pbr";
// Inside a scene directory: its identity and every file with its size and CRC-32.
inline constexpr const char* kSceneRecordFile = "scene_files.json";
// Inside a scene directory: how many parts the bin asked for and took.
inline constexpr const char* kSceneFillFile = "scene_fill.json";
// Inside a scene directory, when the plan sets materials: each part instance's material.
inline constexpr const char* kSceneMaterialsFile = "scene_materials.json";
// Inside a scene directory, when the plan checks picks: each part's verdict and best grasp.
inline constexpr const char* kScenePickableFile = "scene_pickable.json";
// A scene being written lives in "<scene_id>.partial" until it is complete.
inline constexpr const char* kPartialSuffix = ".partial";

// BOP's root camera file: camera.json for a plan of one sensor, else camera_<sensor>.json per sensor.
std::string CameraFileName(const std::vector<std::string>& sensors, size_t sensor_index);

// Six digits, zero-padded: "000042".
std::string SixDigits(uint64_t n);
std::filesystem::path SceneDir(const std::filesystem::path& root, uint64_t scene_id);
std::filesystem::path PartialSceneDir(const std::filesystem::path& root, uint64_t scene_id);

}  // namespace vscan::service::dataset

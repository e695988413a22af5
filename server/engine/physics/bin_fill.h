#pragma once
// Fills an open bin with rigid parts dropped from above it (Bullet, kept inside the .cpp files).
// Deterministic for one seed on one build: one single-threaded world, fixed time steps.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::physics {

// An open bin: a box (the default) or, when mesh has triangles, that mesh.
// Box: the bin frame has the floor's inner surface at z = 0, centred in x and y; the rim is at
// z = inner_size.z().
// Mesh: its triangles (metres, in the bin frame) collide as a static concave mesh; parts drop from
// above its bounding box, within that box's x/y extent, and "inside the bin" is inside that box.
struct BinSpec {
  Eigen::Vector3d inner_size = Eigen::Vector3d(0.30, 0.20, 0.15);  // metres; box only
  double wall_thickness = 0.01;                                    // metres, walls and floor; box only
  Pose3 world_from_bin = Pose3::Identity();
  TriangleMesh mesh;  // empty: the box
};

// Where parts go, in the bin frame: the box's inner box or the mesh's bounding box. The rim is
// hi.z(); wall is how far the bin reaches beyond it at the sides and below (0 for a mesh).
struct BinInterior {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();
  Eigen::Vector3d hi = Eigen::Vector3d::Zero();
  double wall = 0.0;
};
BinInterior InteriorOf(const BinSpec& bin);

enum class PartCollision {
  kConvexHull,  // the convex hull of the mesh, simplified within FillOptions::hull_tolerance_m
  // A compound of convex pieces (plane cuts, convex_decomposition.h), each simplified like the
  // hull; a part's notches and wide bores stay open. Computed once per distinct mesh in a fill.
  kConvexDecomposition,
};

struct PartType {
  std::string name;
  TriangleMesh mesh;  // metres, in the part's frame
  size_t count = 0;
  std::optional<double> mass_kg;  // when unset: density times the mesh's enclosed volume
  double density_kg_per_m3 = 2700.0;
  PartCollision collision = PartCollision::kConvexHull;
};

struct FillOptions {
  uint64_t seed = 1;
  double time_step_s = 1.0 / 240.0;  // one step; within [1e-4, 0.05]
  int substeps = 1;                  // internal Bullet steps per step (time_step_s / substeps each)
  int solver_iterations = 10;
  // A collision hull keeps the fewest of the exact hull's vertices (greedily) such that every
  // exact hull vertex lies within this distance of it; the full hull where that needs all of them.
  // 0.2 mm, under the 0.5 mm collision margin: half the CPU per simulated second of 0.05 mm on
  // parts with 100-300 hull vertices (Bullet's support search is linear in them).
  double hull_tolerance_m = 0.0002;
  double collision_margin_m = 0.0005;
  double friction = 0.6;
  double restitution = 0.0;
  // Rolling and spinning resistance (metres of lever): without it round parts roll for ever.
  double rolling_friction_m = 0.002;
  double linear_damping = 0.05;
  double angular_damping = 0.3;
  // Contacts from the hulls' faces (Bullet's polyhedral clipping): a full manifold every step,
  // so parts resting on a face do not rock.
  bool polyhedral_contacts = true;
  // With polyhedral_contacts: a box bin's floor and walls get faces too, and the contact normal of
  // two hulls with at most 32 edge directions each (a box, the fixture parts) comes from the
  // separating-axis test over their faces and edge pairs, not from GJK/EPA; where either has more
  // (the machined parts' 55-82, where the edge pairs cost too much), over their faces alone.
  // Without it, piles of 50 angle blocks and pins settled with pins 4.4-5.3 mm inside blocks and
  // parts 1-2 mm inside the bin, and piles of machined parts 5-9 mm deep, while Bullet's contacts
  // read under 0.5 mm.
  bool separating_axis_contacts = true;
  // A part is at rest once it has stayed within settle_move_m and settle_turn_rad of where it
  // was settle_steps steps ago (its pose, not its speed: a pile's solver jitter has speed but goes
  // nowhere); the fill is settled when every part is.
  double settle_move_m = 0.001;
  double settle_turn_rad = 0.02;
  int settle_steps = 24;
  // Bullet puts a pile to sleep when all its parts stay under these for 2 s (its deactivation
  // time); a sleeping part has no speed, so it counts as at rest. Zero turns sleeping off.
  double sleep_linear_m_per_s = 0.05;
  double sleep_angular_rad_per_s = 0.5;
  // Once the last drop has fallen below the rim (or is full), every part gets this damping, which
  // takes out the solver's jitter in a pile without moving the parts much: the settle phase.
  double settle_damping = 0.9;
  double max_simulated_s = 60.0;
  // Spawn: up to parts_per_drop parts at once, each at rim + drop_clearance_m above its lowest
  // point, at seeded positions inside the footprint and seeded uniform orientations. The next
  // drop comes when the last one has fallen below the rim or after drop_interval_s.
  int parts_per_drop = 4;
  double drop_clearance_m = 0.02;
  double drop_interval_s = 1.0;
  int spawn_attempts = 24;
  // Once at rest, parts whose meshes overlap one another (or a box bin) by more than this are
  // moved apart (SeparateMeshOverlaps, up to separation_rounds times); 0 only measures.
  double max_mesh_overlap_m = 0.0003;
  int separation_rounds = 24;
  // False: neither measure nor separate (MeshOverlaps stays zero); for comparisons of fill times.
  bool measure_mesh_overlaps = true;
  // A part at rest reaching more than this above the rim makes the bin full.
  double rim_tolerance_m = 0.005;
};

struct PlacedPart {
  size_t type = 0;      // index into the parts given to FillBin
  size_t instance = 0;  // 0 .. count-1 within its type, in spawn order
  Pose3 world_from_part = Pose3::Identity();
};

enum class FillEnd {
  kSettled,    // every part spawned and at rest
  kTimeBound,  // max_simulated_s reached first
  kFull,       // a part could not be spawned clear of the others, or came to rest above the rim
  kCancelled,
};

const char* FillEndName(FillEnd end);

// How far the settled parts' triangle meshes overlap one another and the bin: for each pair, the
// deepest vertex or edge point of either mesh inside the other (metres, >= 0), measured to within
// resolution_m (the true depth of that deepest point lies at most that much deeper).
struct MeshOverlaps {
  double max_part_part_m = 0.0;
  double max_part_bin_m = 0.0;
  double p95_part_part_m = 0.0;  // 95th percentile over the overlapping pairs (0 when none)
  size_t overlapping_pairs = 0;  // part-part pairs whose meshes overlap at all
  double resolution_m = 0.0;
  // The separation after the fill (FillOptions::max_mesh_overlap_m): parts moved, the longest
  // move (metres) and the rounds of moves.
  size_t moved_parts = 0;
  double max_move_m = 0.0;
  int rounds = 0;
};

struct FillResult {
  std::vector<PlacedPart> parts;    // in the bin at the end (not those outside)
  std::vector<PlacedPart> outside;  // ended outside the bin's inner box and were removed
  size_t spawned = 0;
  FillEnd end = FillEnd::kSettled;
  std::string message;
  double simulated_s = 0.0;
  uint64_t steps = 0;
  double setup_wall_s = 0.0;  // shapes and world
  double step_wall_s = 0.0;   // stepping, spawning, the final contact pass and measure_wall_s
  double measure_wall_s = 0.0;  // MeasureMeshOverlaps
  // Deepest overlap of the collision shapes in Bullet's contact manifolds after a final collision
  // pass (metres, >= 0): what the solver saw, not the parts.
  double max_part_part_penetration_m = 0.0;
  double max_part_bin_penetration_m = 0.0;
  // The parts' own triangle meshes at their settled poses (MeasureMeshOverlaps).
  MeshOverlaps mesh_overlap;
};

inline constexpr size_t kMaxFillParts = 500;
// A decomposition's plane cuts clip every triangle for each cut they try and cannot be stopped (on
// a 2-core VM the 5080-triangle riser takes about 0.5 s): a decomposed part has at most this many.
inline constexpr size_t kMaxDecompositionTriangles = 20000;

// INVALID_ARGUMENT naming the field ("bin.inner_size", "parts[1].count", "options.time_step_s")
// for bad input. A set cancel flag ends the run as kCancelled with the parts placed so far.
StatusOr<FillResult> FillBin(const BinSpec& bin, const std::vector<PartType>& parts, const FillOptions& options,
                             const std::atomic<bool>* cancel = nullptr);

// Lets a pile settle again after a change (a part taken out of it): the placed parts start at rest
// where they are and fall, rest and leave the bin by FillBin's rules (the types' counts are not
// used). The result's parts keep their type and instance. INVALID_ARGUMENT naming
// "placed[i].type" or "placed[i].world_from_part", or the fields FillBin names.
StatusOr<FillResult> SettlePile(const BinSpec& bin, const std::vector<PartType>& parts,
                                const std::vector<PlacedPart>& placed, const FillOptions& options,
                                const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::physics

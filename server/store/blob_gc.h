#pragma once
// Garbage collection of blob files. A blob goes only when no row of any table names it: the check
// and the unlink happen under the Database's lock, and pinned blobs (being written for a row not
// yet committed) are skipped. Rows go first and files after, so a crash in between leaves only an
// orphan file, which SweepOrphanBlobs removes at the next start.

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "store/blob_store.h"
#include "store/database.h"
#include "vscan/common/status.h"

namespace vscan::store {

struct CollectedBlobs {
  uint64_t files = 0;
  uint64_t bytes = 0;
};

// Removes those of candidates that no row names any more.
StatusOr<CollectedBlobs> CollectBlobs(Database& database, BlobStore& blobs, const std::vector<std::string>& candidates);

// Removes blob files no row names and stale temp files, when older than min_age (younger ones may
// belong to a write in flight).
StatusOr<CollectedBlobs> SweepOrphanBlobs(Database& database, BlobStore& blobs, std::chrono::seconds min_age);

}  // namespace vscan::store

#pragma once
// /api/bins/{job_id} and /api/bins/{job_id}/replay: a bin fill job as the page draws it (its state,
// the bin and the parts from bin.json) and the bytes of its bin_replay.bin (docs/BINS.md).

#include "web/web_request.h"
#include "web/web_sources.h"

namespace vscan::web {

// segments[0] is "bins".
WebReply ServeBins(const WebSources& sources, const WebRequest& request);

}  // namespace vscan::web

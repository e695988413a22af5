#pragma once
// The two halves of moving a file over a stream: sending a source's bytes in chunk messages after a
// header (mesh and cloud uploads), and receiving chunk messages whose first carries the metadata
// with the total size (artifact and cloud reads).

#include <algorithm>
#include <functional>
#include <string>

#include <grpcpp/client_context.h>
#include <grpcpp/support/sync_stream.h>

#include "vscan/client/types.h"
#include "vscan/common/grpc_status.h"
#include "vscan/common/status.h"

namespace vscan::client {

// Fills up to n bytes at buf; returns how many (0 only at the end).
using ChunkSource = std::function<StatusOr<size_t>(char* buf, size_t n)>;

// Writes first (the header), then size bytes from read in chunk_bytes pieces (set_chunk on a
// Request), then finishes. A local failure (the source ended early or failed) cancels the call
// and is returned; else the server's verdict.
template <typename Request>
Status SendChunks(grpc::ClientContext& context, grpc::ClientWriter<Request>& writer, const Request& first,
                  uint64_t size, size_t chunk_bytes, const ChunkSource& read, const ProgressFn& progress,
                  const char* what) {
  bool open = writer.Write(first);
  Status local;
  uint64_t sent = 0;
  std::string buffer(std::max<size_t>(chunk_bytes, 1), '\0');
  Request message;
  while (open && sent < size) {
    const size_t want = static_cast<size_t>(std::min<uint64_t>(buffer.size(), size - sent));
    auto got = read(buffer.data(), want);
    if (!got.ok() || *got == 0) {
      local = got.ok() ? DataLoss(std::string(what) + " source ended after " + std::to_string(sent) + " of " +
                                  std::to_string(size) + " bytes")
                       : got.status();
      context.TryCancel();
      break;
    }
    message.set_chunk(buffer.data(), *got);
    open = writer.Write(message);
    sent += *got;
    if (open && progress) progress(sent, size);
  }
  if (open && local.ok()) writer.WritesDone();
  const grpc::Status status = writer.Finish();
  if (!local.ok()) return local;
  if (!status.ok()) return FromGrpc(status);
  return Status::Ok();
}

// Reads every message, takes the metadata from the first (meta_of(response)), passes each chunk to
// sink and checks the bytes against size_of(metadata). what names the thing in messages.
template <typename Response, typename Meta, typename MetaOf, typename SizeOf>
StatusOr<Meta> ReceiveChunks(grpc::ClientContext& context, grpc::ClientReader<Response>& reader, MetaOf meta_of,
                             SizeOf size_of, const ArtifactSink& sink, const ProgressFn& progress,
                             const std::string& what) {
  Response response;
  Meta meta;
  bool first = true;
  uint64_t received = 0;
  Status failed;
  while (reader.Read(&response)) {
    if (first) meta = meta_of(response);
    first = false;
    received += response.chunk().size();
    if (received > size_of(meta)) {
      failed = DataLoss(what + ": more than its " + std::to_string(size_of(meta)) + " bytes arrived");
    } else if (sink) {
      failed = sink(response.chunk());
    }
    if (!failed.ok()) {
      context.TryCancel();
      break;
    }
    if (progress) progress(received, size_of(meta));
  }
  const grpc::Status status = reader.Finish();
  if (!failed.ok()) return failed;
  if (!status.ok()) return FromGrpc(status);
  if (received != size_of(meta)) {
    return DataLoss(what + ": got " + std::to_string(received) + " of its " + std::to_string(size_of(meta)) +
                    " bytes");
  }
  return meta;
}

// Reads a file in pieces for SendChunks; *size is its size.
StatusOr<ChunkSource> FileSource(const std::string& path, uint64_t* size);
// Reads bytes in memory, which must outlive the source.
ChunkSource BytesSource(std::string_view bytes);

}  // namespace vscan::client

#pragma once
// Mesh and robot uploads as the CLI runs them (progress bar, exit codes), shared by
// `vscan mesh upload`, `vscan robot upload` and `vscan campaign run`.

#include <string>

#include "session/context.h"

namespace vscan::cli {

// Uploads file; on failure prints the error and returns its exit code (5 when the file cannot be
// read, else the server's), on success returns kExitOk and fills *mesh.
int UploadMesh(Context& ctx, const std::string& file, const client::MeshUploadOptions& options, v1::Mesh* mesh);

// Uploads a bundle directory or URDF file the same way (5 also when a symbolic link in the
// directory leads out of it). urdf_option names the setting that chooses the URDF inside a
// directory, for the message when it is missing.
int UploadRobot(Context& ctx, const std::string& path, const client::RobotUploadOptions& options,
                const std::string& urdf_option, v1::Robot* robot);

}  // namespace vscan::cli

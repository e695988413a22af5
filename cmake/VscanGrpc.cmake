# vscan_grpc: gRPC and protobuf for vscan's libraries. An executable whose VSCAN_STATIC_GRPC
# property is on gets them (with abseil) from their static archives instead of the shared
# libraries: binding the symbols of ~50 shared libraries is most of a short-lived process's
# start-up (see docs/BENCHMARKS.md, "One-shot and idle scans"). Nothing else in such an executable
# may load the shared gRPC or protobuf.
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(VSCAN_GRPC_PC QUIET grpc++ protobuf)
endif()
find_library(VSCAN_GRPCXX_ARCHIVE NAMES libgrpc++.a)
find_library(VSCAN_PROTOBUF_ARCHIVE NAMES libprotobuf.a)
set(VSCAN_GRPC_ARCHIVES_FOUND OFF)
if(VSCAN_GRPC_PC_FOUND AND VSCAN_GRPCXX_ARCHIVE AND VSCAN_PROTOBUF_ARCHIVE)
  set(VSCAN_GRPC_ARCHIVES_FOUND ON)
endif()

add_library(vscan_grpc_archives INTERFACE)
if(VSCAN_GRPC_ARCHIVES_FOUND)
  # pkg-config's static flags name libsystemd, of which Debian ships no archive and which gRPC's
  # archives do not need.
  set(flags ${VSCAN_GRPC_PC_STATIC_LDFLAGS})
  list(REMOVE_ITEM flags -lsystemd)
  target_link_libraries(vscan_grpc_archives INTERFACE
    "-Wl,--start-group" "-Wl,-Bstatic" ${flags} "-Wl,-Bdynamic" "-Wl,--end-group")
endif()

set(static "$<BOOL:$<TARGET_PROPERTY:VSCAN_STATIC_GRPC>>")
add_library(vscan_grpc INTERFACE)
target_link_libraries(vscan_grpc INTERFACE
  "$<$<NOT:${static}>:gRPC::grpc++>"
  "$<$<NOT:${static}>:protobuf::libprotobuf>"
  "$<${static}:vscan_grpc_archives>")
# Headers and definitions are the same either way.
target_include_directories(vscan_grpc INTERFACE
  $<TARGET_PROPERTY:gRPC::grpc++,INTERFACE_INCLUDE_DIRECTORIES>
  $<TARGET_PROPERTY:protobuf::libprotobuf,INTERFACE_INCLUDE_DIRECTORIES>)

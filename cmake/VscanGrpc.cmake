# vscan_grpc: gRPC and protobuf for vscan's libraries. An executable whose VSCAN_STATIC_GRPC
# property is on gets them (with abseil) from their static archives instead of the shared
# libraries: binding the symbols of ~50 shared libraries is most of a short-lived process's
# start-up (see docs/BENCHMARKS.md, "One-shot and idle scans"). Nothing else in such an executable
# may load the shared gRPC or protobuf.
# Only the static link flags are read, with one pkg-config call: pkg_check_modules asks for every
# kind of flag and walked abseil's graph for 18 s of each configure, against 1 s.
find_package(PkgConfig QUIET)
set(grpc_static_libs_rc 1)
if(PkgConfig_FOUND)
  execute_process(COMMAND ${PKG_CONFIG_EXECUTABLE} --static --libs grpc++ protobuf
                  OUTPUT_VARIABLE grpc_static_libs RESULT_VARIABLE grpc_static_libs_rc
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
endif()
find_library(VSCAN_GRPCXX_ARCHIVE NAMES libgrpc++.a)
find_library(VSCAN_PROTOBUF_ARCHIVE NAMES libprotobuf.a)
set(VSCAN_GRPC_ARCHIVES_FOUND OFF)
if(grpc_static_libs_rc EQUAL 0 AND VSCAN_GRPCXX_ARCHIVE AND VSCAN_PROTOBUF_ARCHIVE)
  set(VSCAN_GRPC_ARCHIVES_FOUND ON)
endif()

add_library(vscan_grpc_archives INTERFACE)
if(VSCAN_GRPC_ARCHIVES_FOUND)
  # pkg-config's static flags name libsystemd, of which Debian ships no archive and which gRPC's
  # archives do not need.
  separate_arguments(flags UNIX_COMMAND "${grpc_static_libs}")
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

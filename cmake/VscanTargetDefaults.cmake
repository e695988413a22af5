# Warnings and language level shared by every vscan target.
function(vscan_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-missing-field-initializers)
  # GCC 12 reports false -Wrestrict positives in std::string at -O3 (GCC bug 105329).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  if(VSCAN_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Targets whose files all include the same heavy headers (CLI11, the generated gRPC code) compile
# several sources per translation unit, so those headers are parsed once a batch, not once a file.
option(VSCAN_UNITY_BUILD "Compile the header-heavy targets in batches of sources" ON)
# Large enough that every target is one batch: a second batch of the same target parsed and
# instantiated the same headers again (the gRPC adapters' three batches took 82 s of CPU).
set(VSCAN_UNITY_BATCH_SIZE 64 CACHE STRING "Sources per batch in the batched targets")
function(vscan_unity_build target)
  if(VSCAN_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE BATCH
                          UNITY_BUILD_BATCH_SIZE ${VSCAN_UNITY_BATCH_SIZE})
  endif()
endfunction()

# vscan_unity_groups(target [GROUP name sources...]... [ALONE sources...]): batches for a target
# whose fuzz targets compile some of its sources themselves, instrumented (fuzz/CMakeLists.txt). A
# batch there holds exactly the sources one fuzz target compiles, else the linker would take the
# batch's object from the archive beside the instrumented copies; ALONE sources stay objects of
# their own. Every other source of the target shares one batch.
function(vscan_unity_groups target)
  if(NOT VSCAN_UNITY_BUILD)
    return()
  endif()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE GROUP)
  set(placed "")
  set(group "")
  set(expect_name FALSE)
  foreach(arg IN LISTS ARGN)
    if(arg STREQUAL "GROUP")
      set(expect_name TRUE)
    elseif(arg STREQUAL "ALONE")
      set(group "")
    elseif(expect_name)
      set(group ${arg})
      set(expect_name FALSE)
    else()
      if(group)
        set_source_files_properties(${arg} PROPERTIES UNITY_GROUP ${group})
      endif()
      list(APPEND placed ${arg})
    endif()
  endforeach()
  get_target_property(sources ${target} SOURCES)
  foreach(source IN LISTS sources)
    if(NOT source IN_LIST placed)
      set_source_files_properties(${source} PROPERTIES UNITY_GROUP ${target})
    endif()
  endforeach()
endfunction()

# Release compiles the engine at -O3. A folder whose code spends its time elsewhere asks for less
# here: the service layer, the C++ client and the CLI -O2 (about 15% quicker to compile), the gRPC
# adapters, vscand's own files and the tests -O1 (a third quicker), the generated messages -O0; they
# hand the heavy work to the -O3 libraries and to libprotobuf.
function(vscan_release_optimisation level)
  add_compile_options($<$<CONFIG:Release>:${level}>)
endfunction()

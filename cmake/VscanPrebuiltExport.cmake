# Writes <build>/prebuilt/vscan-targets.cmake: every library of this build as an imported target
# named prebuilt::<name>. The clang fuzz build (fuzz/CMakeLists.txt) links the server from there
# instead of compiling it a second time; both compilers use libstdc++, so the archives mix.
function(vscan_collect_libraries dir out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  set(libraries)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(type MATCHES "^(STATIC|SHARED|INTERFACE)_LIBRARY$")
      list(APPEND libraries ${target})
    endif()
  endforeach()
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(subdir IN LISTS subdirs)
    vscan_collect_libraries(${subdir} sub)
    list(APPEND libraries ${sub})
  endforeach()
  set(${out} ${libraries} PARENT_SCOPE)
endfunction()

function(vscan_export_prebuilt)
  vscan_collect_libraries(${PROJECT_SOURCE_DIR} libraries)
  export(TARGETS ${libraries} NAMESPACE prebuilt:: FILE ${PROJECT_BINARY_DIR}/prebuilt/vscan-targets.cmake)
endfunction()

# ctest runs this with cmake -P (tests/CMakeLists.txt): the library as another project sees it (SPEC §8).
#   MODE=example:      installs BUILD_DIR into a fresh prefix, then configures, builds and runs examples/minimal_host
#                      against that prefix alone (find_package(ssvgi)), and compiles resolve_include_check.comp with
#                      GLSLC against the prefix's include folder alone (the resolve a host's composite includes).
#   MODE=library-only: configures SOURCE_DIR with only the library, every package the library does not need
#                      refused, so that looking for one fails the configure.
foreach(variable MODE SOURCE_DIR WORK_DIR GENERATOR CXX_COMPILER GLSLC)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "installed_package_test.cmake needs -D${variable}=")
  endif()
endforeach()

file(REMOVE_RECURSE ${WORK_DIR})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    string(JOIN " " command ${ARGN})
    message(FATAL_ERROR "failed (${result}): ${command}")
  endif()
endfunction()

if(MODE STREQUAL "example")
  run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
  # The prefix is the only place to look: no package registry, which could hold a build tree.
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/minimal_host -B ${WORK_DIR}/build -G ${GENERATOR}
      -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
      -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
  run(${WORK_DIR}/build/minimal_host)
  run(${GLSLC} --target-env=vulkan1.1 -I ${WORK_DIR}/prefix/include -o ${WORK_DIR}/resolve_include_check.spv
      ${SOURCE_DIR}/tests/resolve_include_check.comp)
elseif(MODE STREQUAL "library-only")
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR} -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
      -DSSVGI_BUILD_RENDERER=OFF -DSSVGI_BUILD_TESTS=OFF
      -DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON -DCMAKE_DISABLE_FIND_PACKAGE_CLI11=ON
      -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=ON -DCMAKE_DISABLE_FIND_PACKAGE_TinyGLTF=ON
      -DCMAKE_DISABLE_FIND_PACKAGE_tinyexr=ON)
else()
  message(FATAL_ERROR "unknown MODE ${MODE}")
endif()

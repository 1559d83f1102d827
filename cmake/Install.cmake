# `cmake --install` installs the GI library as a CMake package: find_package(ssvgi) then
# target_link_libraries(app PRIVATE ssvgi::ssvgi). The SPIR-V is embedded in the library (cmake/Shaders.cmake), so
# nothing of the build or source tree is needed at run time.
#
# ssvgi is a static library, so the static library of its Vulkan layer (ssvgi_gpu) is installed and exported too — as
# a link dependency only, its headers are not installed: ssvgi.h is the whole API.
include(CMakePackageConfigHelpers)

set(SSVGI_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/ssvgi)

install(TARGETS ssvgi ssvgi_gpu EXPORT ssvgiTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/ssvgi DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT ssvgiTargets NAMESPACE ssvgi:: DESTINATION ${SSVGI_INSTALL_CMAKEDIR})

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/ssvgiConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/ssvgiConfig.cmake
                              INSTALL_DESTINATION ${SSVGI_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ssvgiConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/ssvgiConfig.cmake ${PROJECT_BINARY_DIR}/ssvgiConfigVersion.cmake
        DESTINATION ${SSVGI_INSTALL_CMAKEDIR})

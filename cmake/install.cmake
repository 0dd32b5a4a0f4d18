# The installed package: `cmake --install build --prefix P` gives P/include/cdbench/ (the
# engine's headers at their "cdbench/<dir>/<file>.h" paths, and cdbench/cdbench.h, the public
# API), the static libraries in P/lib, and P/lib/cmake/cdbench, which find_package(cdbench)
# reads: the targets cdbench::cdbench (the public API), cdbench::engine and what they link,
# with paths relative to P, so the prefix can move (docs/library.md "Installing").
include(CMakePackageConfigHelpers)
set(cdb_package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/cdbench)
set_target_properties(cdb_api PROPERTIES EXPORT_NAME cdbench)
set_target_properties(cdb_engine PROPERTIES EXPORT_NAME engine)
set_target_properties(cdb_registry PROPERTIES EXPORT_NAME registry)
set_target_properties(cdb_baselines PROPERTIES EXPORT_NAME baselines)
install(TARGETS cdb_api cdb_engine cdb_registry cdb_baselines EXPORT cdbenchTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/lib/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cdbench
        FILES_MATCHING PATTERN "*.h" PATTERN "*.cuh")
install(FILES ${PROJECT_SOURCE_DIR}/api/cdbench.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cdbench)
install(EXPORT cdbenchTargets NAMESPACE cdbench:: DESTINATION ${cdb_package_dir})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/cdbenchConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/package/cdbenchConfig.cmake INSTALL_DESTINATION ${cdb_package_dir})
# 0.x: a new minor version may change the API.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/package/cdbenchConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/package/cdbenchConfig.cmake ${CMAKE_BINARY_DIR}/package/cdbenchConfigVersion.cmake
        DESTINATION ${cdb_package_dir})

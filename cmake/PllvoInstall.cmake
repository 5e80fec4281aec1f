# `cmake --install build --prefix P`: the library (static, with the pllvo::pllvo target that
# find_package(pllvo) gives), its headers, the `pllvo` program, the default config files and
# pllvo's own network weights, found at run time relative to the install:
#   P/lib/libpllvo.a, P/include/pllvo/..., P/lib/cmake/pllvo/, P/bin/pllvo,
#   P/share/pllvo/config/*.yaml, P/share/pllvo/models/*.safetensors,
#   P/lib/pllvo/python/pllvo/ (the Python module, when built)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS pllvo pllvo_torch EXPORT pllvoTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS pllvo_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# Every header: the API's (pllvo/api/) include a few others, and the internal ones stay usable.
install(DIRECTORY "${PROJECT_SOURCE_DIR}/src/pllvo" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
install(DIRECTORY "${PROJECT_SOURCE_DIR}/config/" DESTINATION ${CMAKE_INSTALL_DATADIR}/pllvo/config
        FILES_MATCHING PATTERN "*.yaml")
install(FILES "${PROJECT_SOURCE_DIR}/models/pllvo_superpoint_v1.safetensors"
              "${PROJECT_SOURCE_DIR}/models/pllvo_lightglue_v1.safetensors"
              "${PROJECT_SOURCE_DIR}/models/README.md"
        DESTINATION ${CMAKE_INSTALL_DATADIR}/pllvo/models)

install(EXPORT pllvoTargets NAMESPACE pllvo:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pllvo)
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/pllvoConfig.cmake.in"
                              "${PROJECT_BINARY_DIR}/pllvoConfig.cmake"
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pllvo
                              PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file("${PROJECT_BINARY_DIR}/pllvoConfigVersion.cmake"
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/pllvoConfig.cmake" "${PROJECT_BINARY_DIR}/pllvoConfigVersion.cmake"
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/pllvo)

# `cmake --install build [--prefix P]`: the libraries, the public headers, the
# CLI and a CMake package, so another project can
#   find_package(meniscus REQUIRED)
#   target_link_libraries(app PRIVATE meniscus::meniscus)
# (tests/consumer/ is such a project; the ctest test install.find_package
# builds and runs it against an install of this build).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(MENISCUS_INSTALL_TARGETS meniscus meniscus_core meniscus_io meniscus_surface meniscus_sim meniscus_cpu)
if(MENISCUS_HAVE_GL)
  list(APPEND MENISCUS_INSTALL_TARGETS meniscus_gl)
endif()
if(MENISCUS_HAVE_FFMPEG)
  list(APPEND MENISCUS_INSTALL_TARGETS meniscus_video)
endif()
if(MENISCUS_HAVE_MPI)
  list(APPEND MENISCUS_INSTALL_TARGETS meniscus_mpi)
endif()
install(TARGETS ${MENISCUS_INSTALL_TARGETS} EXPORT meniscusTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS meniscus_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/meniscus DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
set(MENISCUS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/meniscus)
install(EXPORT meniscusTargets NAMESPACE meniscus:: DESTINATION ${MENISCUS_CMAKE_DIR})
configure_package_config_file(cmake/meniscusConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/meniscusConfig.cmake INSTALL_DESTINATION ${MENISCUS_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/meniscusConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/meniscusConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/meniscusConfigVersion.cmake
        DESTINATION ${MENISCUS_CMAKE_DIR})

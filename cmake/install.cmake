# `cmake --install`: the sdm program, the four libraries and their headers, a CMake package
# (find_package(sdm) gives sdm::stm, sdm::sdm and the layers sdm::core, sdm::render, sdm::transfer,
# sdm::maps), a pkg-config file and the licence. Included from the top-level CMakeLists.txt.
include(CMakePackageConfigHelpers)

install(TARGETS sdm RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS sdm-full RUNTIME DESTINATION ${CMAKE_INSTALL_LIBEXECDIR}/sdm)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/python/sdm_batch.py DESTINATION ${CMAKE_INSTALL_DATADIR}/sdm)
install(FILES ${PROJECT_SOURCE_DIR}/python/sdm_batch_report.py DESTINATION ${CMAKE_INSTALL_DATADIR}/sdm)
install(TARGETS sdm_core sdm_render sdm_transfer sdm_maps sdm_stm sdm_all osd_cpu EXPORT sdmTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sdm)
foreach(dir libstm libsdm)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sdm FILES_MATCHING PATTERN "*.h")
endforeach()
install(FILES ${PROJECT_BINARY_DIR}/generated/libstm/core/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sdm/libstm/core)

set(SDM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/sdm)
install(EXPORT sdmTargets NAMESPACE sdm:: DESTINATION ${SDM_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/sdmConfig.cmake.in ${PROJECT_BINARY_DIR}/sdmConfig.cmake
                              INSTALL_DESTINATION ${SDM_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/sdmConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/sdmConfig.cmake ${PROJECT_BINARY_DIR}/sdmConfigVersion.cmake DESTINATION ${SDM_CMAKE_DIR})

# pkg-config: the static libraries in link order and what they need.
set(SDM_PC_LIBS "-lsdm_maps -lsdm_transfer -lsdm_render -lsdm_core -lOpenMeshTools -lOpenMeshCore -ltinygltf ${OSD_CPU_LIBRARY}")
if(CHOLMOD_LIBRARY AND CHOLMOD_INCLUDE_DIR)
  string(APPEND SDM_PC_LIBS " ${CHOLMOD_LIBRARY}")
endif()
# The prefix relative to the .pc file, so the installed tree can move (--prefix at install time).
file(RELATIVE_PATH SDM_PC_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
configure_file(${PROJECT_SOURCE_DIR}/cmake/sdm.pc.in ${PROJECT_BINARY_DIR}/sdm.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/sdm.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/sdm)

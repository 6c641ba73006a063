# Install rules and Debian packages (CPack). `cmake --install build --prefix P` lays out
#   P/bin/uav-*                      the programs (each finds its data in P/share/uav)
#   P/share/uav/{vehicles,cameras,scenes,areas}   vehicle files, camera files, scenes, areas
#   P/share/doc/uav/                 README and the manual (docs/, with its pictures and records)
# and, for the packages only (prefix /usr): /etc/uav (uav-onboard's configuration), the systemd
# unit, the desktop entry and icon. `cpack --config build/CPackConfig.cmake` builds four packages:
#   uav-common   data, documentation, uav-keygen
#   uav-gcs      the ground control station (desktop entry, icon)
#   uav-onboard  the vehicle's flight stack (systemd unit, /etc/uav, the `uav` system user)
#   uav-tools    the command-line tools (one per capability) and uav-demo, the main job
include(GNUInstallDirs)
set(_pkg ${PROJECT_SOURCE_DIR}/resources/packaging)

install(TARGETS uav-keygen RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT common)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/resources/vehicles ${PROJECT_SOURCE_DIR}/resources/cameras
                  ${PROJECT_SOURCE_DIR}/resources/scenes ${PROJECT_SOURCE_DIR}/resources/areas
        DESTINATION ${CMAKE_INSTALL_DATADIR}/uav COMPONENT common)
# The manual as in the source tree, so that its relative links and pictures work where it is
# installed: README.md, docs/, and the screenshots and benchmark records it links to.
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/uav COMPONENT common)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/uav COMPONENT common)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/resources/screenshots ${PROJECT_SOURCE_DIR}/resources/benchmarks
        DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/uav/resources COMPONENT common)

install(TARGETS uav-gcs RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT gcs)
install(FILES ${_pkg}/uav-gcs/uav-gcs.desktop DESTINATION ${CMAKE_INSTALL_DATADIR}/applications COMPONENT gcs)
install(FILES ${_pkg}/uav-gcs/uav-gcs.svg DESTINATION ${CMAKE_INSTALL_DATADIR}/icons/hicolor/scalable/apps COMPONENT gcs)

install(TARGETS uav-onboard RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT onboard)
install(FILES ${_pkg}/uav-onboard/uav-onboard.service DESTINATION lib/systemd/system COMPONENT onboard)
# Its configuration in /etc/uav for a system install (prefix /usr, as the package); for any other
# prefix beside the data (PREFIX/share/uav/etc), so that `cmake --install --prefix ~/uav` never
# writes outside its prefix. Decided when installing, by the prefix then in effect.
install(CODE "
  if(CMAKE_INSTALL_PREFIX STREQUAL \"/usr\")
    set(uav_etc /etc/uav)
  else()
    set(uav_etc \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_DATADIR}/uav/etc\")  # file(INSTALL) adds DESTDIR
  endif()
  file(INSTALL ${_pkg}/uav-onboard/onboard.conf DESTINATION \${uav_etc})
  file(INSTALL ${PROJECT_SOURCE_DIR}/resources/vehicles/x650.params DESTINATION \${uav_etc} RENAME vehicle.params)
" COMPONENT onboard)

install(TARGETS uav-survey uav-avoid-bench uav-ulion-bench uav-render uav-sysid uav-vo uav-vo-eval uav-active-stereo
                uav-powerlines uav-powerlines-train uav-monodepth uav-stereo uav-stereo-error uav-stereo-calibrate uav-track uav-stitch
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
install(PROGRAMS ${CMAKE_BINARY_DIR}/bin/uav-demo DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)

# ---- Debian packages
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME uav)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "UAV GCS and onboard flight stack")
set(CPACK_PACKAGE_CONTACT "UAV team <uav-team@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "UAV ground control station and onboard flight stack")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_INSTALL_PREFIX /usr)  # with CPACK_SET_DESTDIR the staged prefix is this one
set(CPACK_STRIP_FILES ON)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_COMPRESSION_TYPE xz)
set(CPACK_COMPONENTS_ALL common gcs onboard tools)
set(CPACK_INSTALL_CMAKE_PROJECTS "${CMAKE_BINARY_DIR};${PROJECT_NAME};ALL;/")
set(CPACK_CMAKE_GENERATOR ${CMAKE_GENERATOR})
# Staged with DESTDIR under the real prefix, so the install step above sees /usr and fills /etc.
set(CPACK_SET_DESTDIR ON)
foreach(c COMMON GCS ONBOARD TOOLS)
  string(TOLOWER ${c} lc)
  set(CPACK_DEBIAN_${c}_PACKAGE_NAME uav-${lc})
endforeach()
set(CPACK_DEBIAN_COMMON_DESCRIPTION "UAV: vehicle files, cameras, scenes, the manual and uav-keygen")
set(CPACK_DEBIAN_GCS_DESCRIPTION "UAV ground control station: plan, fly, track, download maps (Dear ImGui)")
set(CPACK_DEBIAN_GCS_PACKAGE_RECOMMENDS "espeak-ng")
set(CPACK_DEBIAN_ONBOARD_DESCRIPTION "UAV onboard flight stack: control, navigation, vision workers, GCS link")
set(CPACK_DEBIAN_ONBOARD_PACKAGE_DEPENDS "adduser")
set(CPACK_DEBIAN_ONBOARD_PACKAGE_CONTROL_EXTRA
    ${_pkg}/uav-onboard/postinst ${_pkg}/uav-onboard/prerm ${_pkg}/uav-onboard/conffiles)
set(CPACK_DEBIAN_TOOLS_DESCRIPTION "UAV command-line tools: survey, stereo, power lines, tracking, VO, stitching, benchmarks")
include(CPack)
cpack_add_component(common DISPLAY_NAME "Data and documentation")
cpack_add_component(gcs DISPLAY_NAME "Ground control station" DEPENDS common)
cpack_add_component(onboard DISPLAY_NAME "Onboard flight stack" DEPENDS common)
cpack_add_component(tools DISPLAY_NAME "Command-line tools" DEPENDS common)

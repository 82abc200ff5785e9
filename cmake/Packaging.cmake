# Installation layout and the Debian packages (`make package`, CPack DEB, one package per
# component): `probeless`, the appliance (the binary, the systemd unit, sysusers, tmpfiles and
# udev files, the default config as a conffile), and `probeless-lab`, the development tools
# (`probeless eval`, `probeless bench`: the lab binary, which brings OpenCV). docs/appliance.md
# describes what each file does.
include(GNUInstallDirs)
set(CMAKE_INSTALL_DEFAULT_COMPONENT_NAME appliance)

install(TARGETS probeless RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT appliance)
# app/cli/lab_dispatch.cpp finds it at ../lib/probeless/ from the appliance binary.
install(TARGETS probeless-lab RUNTIME DESTINATION lib/probeless COMPONENT lab)
# Debian 12 has merged /usr: systemd reads units, sysusers, tmpfiles and udev rules here.
install(FILES ${PROJECT_SOURCE_DIR}/systemd/probeless.service ${PROJECT_SOURCE_DIR}/systemd/probeless.socket
  DESTINATION lib/systemd/system)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/probeless.sysusers DESTINATION lib/sysusers.d
        RENAME probeless.conf)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/probeless.tmpfiles DESTINATION lib/tmpfiles.d
        RENAME probeless.conf)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/60-probeless.rules DESTINATION lib/udev/rules.d)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/probeless.toml DESTINATION /etc/probeless)
# Board files (docs/boards.md): `board = "rpi5"` in the config finds them here
# (app/pipeline/board_file.cpp looks in /usr/share/probeless/board).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/board/ DESTINATION ${CMAKE_INSTALL_DATADIR}/probeless/board)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/docs/appliance.md
              ${PROJECT_SOURCE_DIR}/docs/configuration.md ${PROJECT_SOURCE_DIR}/docs/boards.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL appliance lab)
set(CPACK_PACKAGE_NAME probeless)
set(CPACK_DEBIAN_APPLIANCE_PACKAGE_NAME probeless)
set(CPACK_DEBIAN_LAB_PACKAGE_NAME probeless-lab)
set(CPACK_PACKAGE_VENDOR probeless)
set(CPACK_PACKAGE_CONTACT "probeless maintainers <maintainers@probeless.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Headless mixed-reality appliance service")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION video)
# Libraries by dpkg-shlibdeps; among them, since world anchoring with a marker (issue #17),
# libopencv-core406, -imgproc406, -calib3d406 and -contrib406 (the package of
# libopencv_aruco). Debian's -contrib406 depends on much of OpenCV (highgui, dnn, Qt 5,
# tesseract): the appliance's install grows by those packages though the binary loads only
# six libopencv (tests/check_appliance_deps.sh; docs/appliance.md "OpenCV in the appliance").
# The run-time drivers that are loaded, not linked, by hand:
# an OpenCL ICD (PoCL on a desktop, the board's own where it has one) and Mesa's EGL/GL.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_APPLIANCE_PACKAGE_DEPENDS
    "pocl-opencl-icd | opencl-icd, libegl-mesa0, libgl1-mesa-dri, systemd (>= 252)")
# The lab runs the appliance's stages, so it needs the same run-time drivers, plus OpenCV
# (found by dpkg-shlibdeps from the lab binary).
set(CPACK_DEBIAN_LAB_PACKAGE_DEPENDS "probeless (= ${PROJECT_VERSION})")
set(CPACK_COMPONENT_LAB_DESCRIPTION
    "Evaluations and benchmarks of the probeless appliance (probeless eval, probeless bench)")
# The RTSP output's GStreamer elements are plugins, loaded by name at run time; it is off by
# default, so they are recommended rather than required (docs/outputs.md "RTSP").
set(CPACK_DEBIAN_APPLIANCE_PACKAGE_RECOMMENDS
    "gstreamer1.0-plugins-base, gstreamer1.0-plugins-good, gstreamer1.0-plugins-ugly")
set(CPACK_DEBIAN_APPLIANCE_PACKAGE_CONTROL_EXTRA
    ${PROJECT_SOURCE_DIR}/cmake/deb/conffiles ${PROJECT_SOURCE_DIR}/cmake/deb/postinst
    ${PROJECT_SOURCE_DIR}/cmake/deb/prerm ${PROJECT_SOURCE_DIR}/cmake/deb/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)

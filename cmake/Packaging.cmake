# The installation layout, in three components. debian/rules (`make deb`) installs two of
# them into debian/tmp and packages them: `appliance` (the binary, the default config, the
# board files, the docs) as `probeless`, and `lab` (`probeless eval`, `bench`, `calibrate`:
# the lab binary, which brings OpenCV) as `probeless-lab`. The third, `systemd` (the unit,
# socket, sysusers, tmpfiles and udev files), is for a plain `cmake --install`: the package
# has debhelper install those same files from debian/ (symlinks into systemd/), as its
# maintainer scripts need. docs/appliance.md describes what each file does.
include(GNUInstallDirs)
set(CMAKE_INSTALL_DEFAULT_COMPONENT_NAME appliance)

install(TARGETS probeless RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT appliance)
# app/cli/lab_dispatch.cpp finds it at ../lib/probeless/ from the appliance binary.
install(TARGETS probeless-lab RUNTIME DESTINATION lib/probeless COMPONENT lab)
# Debian 12 has merged /usr: systemd reads units, sysusers, tmpfiles and udev rules here.
install(FILES ${PROJECT_SOURCE_DIR}/systemd/probeless.service ${PROJECT_SOURCE_DIR}/systemd/probeless.socket
  DESTINATION lib/systemd/system COMPONENT systemd)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/probeless.sysusers DESTINATION lib/sysusers.d
        RENAME probeless.conf COMPONENT systemd)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/probeless.tmpfiles DESTINATION lib/tmpfiles.d
        RENAME probeless.conf COMPONENT systemd)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/60-probeless.rules DESTINATION lib/udev/rules.d
        COMPONENT systemd)
install(FILES ${PROJECT_SOURCE_DIR}/systemd/probeless.toml DESTINATION /etc/probeless)
# Board files (docs/boards.md): `board = "rpi5"` in the config finds them here
# (app/pipeline/board_file.cpp looks in /usr/share/probeless/board).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/board/ DESTINATION ${CMAKE_INSTALL_DATADIR}/probeless/board)
install(FILES ${PROJECT_SOURCE_DIR}/docs/probeless.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/docs/appliance.md
              ${PROJECT_SOURCE_DIR}/docs/configuration.md ${PROJECT_SOURCE_DIR}/docs/boards.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

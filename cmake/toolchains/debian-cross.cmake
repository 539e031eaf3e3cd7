# What a cross build for a Debian 12 box has in common, whatever its architecture
# (toolchains/arm64.cmake, toolchains/armhf.cmake set the triplet first). Debian's cross
# compilers are multiarch: they find the target's headers and libraries where the
# `:arm64` / `:armhf` packages put them (/usr/lib/<triplet>, /usr/include/<triplet>), so
# no sysroot is needed; scripts/package.sh installs those packages.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_C_COMPILER ${UNIMA_TARGET_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${UNIMA_TARGET_TRIPLET}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${UNIMA_TARGET_TRIPLET})
set(PKG_CONFIG_EXECUTABLE ${UNIMA_TARGET_TRIPLET}-pkg-config CACHE FILEPATH "pkg-config of the target")
# Test programs (and gtest_discover_tests, which lists a test binary's tests at build
# time) run under qemu-user with the target's loader and C library both from libc6:<arch>
# (/lib/ld-linux-*.so, /lib/<triplet>), as on the box: `-L /` looks nowhere else. Not
# `-L /usr/<triplet>`: its loader is the cross toolchain's libc6-<arch>-cross, frozen at
# Debian 12's release, while the C library it then loads (via /etc/ld.so.cache) is
# libc6:<arch> with its updates. The two share the private _rtld_global, whose layout
# moved between those versions: the first new thread's stack search loops forever.
# Cached, so that tests/packaging/cross_smoke.sh runs the daemon with the same emulator;
# forced, so that an existing build tree follows an edit of this line.
set(CMAKE_CROSSCOMPILING_EMULATOR ${UNIMA_QEMU} -L / CACHE STRING "runs the target's programs on this machine" FORCE)
# Debian 12's libyaml-cpp-dev is not Multi-Arch: same (installing the target's would
# remove the host's), so the target's runtime library (libyaml-cpp0.7:<arch>) is used with
# the host's headers of the same version (cross/yaml-cpp/yaml-cpp-config.cmake).
set(yaml-cpp_DIR ${CMAKE_CURRENT_LIST_DIR}/../cross/yaml-cpp CACHE PATH "yaml-cpp for the target")
# The Debian package's Architecture field and file name.
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${UNIMA_DEB_ARCH} CACHE STRING "Debian architecture of the package")

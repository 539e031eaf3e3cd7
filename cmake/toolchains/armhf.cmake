# Cross build for Debian 12 armhf (ARMv7, hard float): 32-bit Raspberry Pi OS and
# Revolution Pi images (bookworm), Debian 12 on armhf boxes. Used by scripts/package.sh armhf.
set(UNIMA_DEB_ARCH armhf)
set(UNIMA_TARGET_TRIPLET arm-linux-gnueabihf)
set(UNIMA_QEMU qemu-arm-static)
set(CMAKE_SYSTEM_PROCESSOR arm)
include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)
# GCC prints a note (-Wpsabi) for each std::vector iterator passed by value: 32-bit ARM's
# calling convention for it changed in GCC 7.1, which matters only beside code built by GCC
# 6 or older (Debian 12 has none). Silenced, so that what the build log shows is worth reading.
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")

# Cross build for Debian 12 arm64: Raspberry Pi OS and Revolution Pi images (bookworm,
# 64-bit), Debian 12 on arm64 boxes. Used by scripts/package.sh arm64.
set(UNIMA_DEB_ARCH arm64)
set(UNIMA_TARGET_TRIPLET aarch64-linux-gnu)
set(UNIMA_QEMU qemu-aarch64-static)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)

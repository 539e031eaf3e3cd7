// The USB adapter's latency timer, found through the device's real path in a sysfs tree
// (a fake one in a temporary directory: the test machine has no adapter).

#include <gtest/gtest.h>

#include <fstream>

#include "io/modbus/usb_latency.hpp"
#include "tests/integration/harness.hpp"

namespace unima::test {
namespace {

namespace fs = std::filesystem;

class UsbLatency : public ::testing::Test {
 protected:
  void SetUp() override {
    sysfs = dir.path() / "sys";
    const auto adapter = sysfs / "bus" / "usb-serial" / "devices" / "ttyUSB3";
    fs::create_directories(adapter);
    fs::create_directories(sysfs / "bus" / "usb-serial" / "devices" / "ttyUSB0");
    std::ofstream(adapter / "latency_timer") << "16\n";
    std::ofstream(sysfs / "bus" / "usb-serial" / "devices" / "ttyUSB0" / "latency_timer") << "2\n";
    // /dev/ttyUSB3 and a by-id link to it, as udev makes them.
    fs::create_directories(dir.path() / "dev" / "serial" / "by-id");
    std::ofstream(dir.path() / "dev" / "ttyUSB3");
    fs::create_symlink("../../ttyUSB3", dir.path() / "dev" / "serial" / "by-id" / "usb-FTDI_FT232R-if00-port0");
  }
  TempDir dir;
  fs::path sysfs;
};

TEST_F(UsbLatency, FoundThroughTheDevicesRealPath) {
  const auto timer = io::find_latency_timer((dir.path() / "dev/serial/by-id/usb-FTDI_FT232R-if00-port0").string(), sysfs);
  ASSERT_TRUE(timer);
  EXPECT_EQ(timer->value, std::chrono::milliseconds(16));
  EXPECT_EQ(timer->file, sysfs / "bus/usb-serial/devices/ttyUSB3/latency_timer");
}

TEST_F(UsbLatency, NoneForADeviceThatIsNoUsbAdapter) {
  std::ofstream(dir.path() / "dev" / "ttyS0");
  EXPECT_FALSE(io::find_latency_timer((dir.path() / "dev/ttyS0").string(), sysfs));
  EXPECT_FALSE(io::find_latency_timer((dir.path() / "dev/missing").string(), sysfs));
}

TEST_F(UsbLatency, SetToOneMillisecond) {
  auto timer = io::find_latency_timer((dir.path() / "dev/ttyUSB3").string(), sysfs);
  ASSERT_TRUE(timer);
  std::string error;
  ASSERT_TRUE(io::set_latency_timer(*timer, std::chrono::milliseconds(1), error)) << error;
  EXPECT_EQ(timer->value, std::chrono::milliseconds(1));
  EXPECT_EQ(io::find_latency_timer((dir.path() / "dev/ttyUSB3").string(), sysfs)->value, std::chrono::milliseconds(1));
}

}  // namespace
}  // namespace unima::test

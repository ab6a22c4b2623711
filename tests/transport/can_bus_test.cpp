// The in-memory CAN bus the daemon's tests and replays use: filters on identifier and frame format
// (error frames always pass, and are counted), FIFO reads, a read that times out, writes recorded.
// (SocketCanBus needs a vcan interface: tools/can_cli_e2e_test.cpp runs it where one exists.)
#include "inertial/transport/can_bus.hpp"

#include <gtest/gtest.h>

namespace inertial {
namespace {

CanFrame Frame(std::uint32_t id, bool extended, std::uint8_t first_byte) {
  CanFrame f;
  f.id = id;
  f.extended = extended;
  f.length = 1;
  f.data[0] = first_byte;
  return f;
}

TEST(InMemoryCanBus, FiltersOrderTimeoutsAndWrites) {
  InMemoryCanBus bus;
  CanFrame f;
  EXPECT_FALSE(bus.Read(&f, 1));  // nothing yet: times out
  bus.Push(Frame(0x10, false, 1));  // no filter: everything passes
  bus.SetFilters({CanId{0x10, false}, CanId{0x20, true}});
  bus.Push(Frame(0x20, false, 2));  // 0x20 only in the 29-bit format: dropped
  bus.Push(Frame(0x20, true, 3));
  bus.Push(Frame(0x30, false, 4));  // not in the filter: dropped
  CanFrame error;
  error.error = true;
  error.id = 0x4;
  bus.Push(error);  // error frames always pass
  bus.Push(Frame(0x10, false, 5));
  EXPECT_EQ(bus.error_frames(), 1u);
  const int expected[] = {1, 3, -1, 5};  // -1: the error frame
  for (int e : expected) {
    ASSERT_TRUE(bus.Read(&f, 0));
    if (e < 0) {
      EXPECT_TRUE(f.error);
    } else {
      EXPECT_EQ(f.data[0], e);
    }
  }
  EXPECT_FALSE(bus.Read(&f, 1));
  bus.Write(Frame(0x7, false, 9));
  bus.Write(Frame(0x8, true, 10));
  ASSERT_EQ(bus.written().size(), 2u);
  EXPECT_EQ(bus.written()[1].id, 0x8u);
  EXPECT_TRUE(bus.written()[1].extended);
  EXPECT_FALSE(bus.Read(&f, 1));  // writes are not read back
}

}  // namespace
}  // namespace inertial

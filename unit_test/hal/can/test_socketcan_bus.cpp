// What can be checked of SocketCanBus on any machine, CAN in the kernel or not.
// The real-traffic checks run inside the vcan VM (unit_test/integration/).
#include <cerrno>

#include "hal/can/socketcan_bus.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::hal;
using rse::core::Status;

TEST_GROUP(SocketCanBus){};

TEST(SocketCanBus, MissingInterfaceIsUnavailableWithTheReason) {
    SocketCanBus bus;
    CHECK(Status::kUnavailable == bus.open("rse_nocan9"));
    // EAFNOSUPPORT where the kernel has no CAN, ENODEV where it has but the name is unknown.
    CHECK(bus.lastErrno() == EAFNOSUPPORT || bus.lastErrno() == ENODEV);
    CHECK_FALSE(bus.isOpen());
    CHECK(CanBusState::kDown == bus.state());
}

TEST(SocketCanBus, UnopenedBusRefusesCleanly) {
    SocketCanBus bus;
    CanFrame f;
    f.id = 0x123;
    f.dlc = 1;
    CHECK(Status::kUnavailable == bus.send(f));
    CHECK(Status::kUnavailable == bus.receive(&f));
    CHECK(Status::kUnavailable == bus.setFilters(nullptr, 0));
    LONGS_EQUAL(1, bus.stats().txUnavailable);
}

TEST(SocketCanBus, BadNamesAndFramesAreRejectedBeforeTheKernel) {
    SocketCanBus bus;
    CHECK(Status::kInvalidArgument == bus.open(""));
    CHECK(Status::kInvalidArgument == bus.open(nullptr));
    CHECK(Status::kInvalidArgument == bus.open("a-name-longer-than-ifnamsiz"));
    CanFrame f;
    f.id = 0x900;  // not a standard id
    CHECK(Status::kInvalidArgument == bus.send(f));
    LONGS_EQUAL(1, bus.stats().txInvalid);
}

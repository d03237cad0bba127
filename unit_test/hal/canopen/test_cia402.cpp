#include "hal/canopen/cia402.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::hal::cia402;

TEST_GROUP(Cia402){};

TEST(Cia402, DecodesEveryStateOfTheIcdTableWhateverTheOtherBits) {
    struct Case {
        std::uint16_t sw;
        PowerState state;
    };
    const Case cases[] = {
        {0x0000, PowerState::kNotReadyToSwitchOn}, {0x0040, PowerState::kSwitchOnDisabled},
        {0x0021, PowerState::kReadyToSwitchOn},    {0x0023, PowerState::kSwitchedOn},
        {0x0027, PowerState::kOperationEnabled},   {0x0007, PowerState::kQuickStopActive},
        {0x000F, PowerState::kFaultReactionActive}, {0x0008, PowerState::kFault},
    };
    for (const Case& c : cases) {
        CHECK(c.state == decodeStatusword(c.sw));
        // Bits outside the pattern (remote, target reached, warning, manufacturer) do not matter.
        CHECK(c.state == decodeStatusword(static_cast<std::uint16_t>(c.sw | 0xFE00 | 0x0080 | 0x0010)));
    }
}

TEST(Cia402, ControlwordWalksTowardsOperationEnabled) {
    LONGS_EQUAL(controlword::kShutdown, controlwordTowardsEnabled(PowerState::kSwitchOnDisabled));
    LONGS_EQUAL(controlword::kSwitchOn, controlwordTowardsEnabled(PowerState::kReadyToSwitchOn));
    LONGS_EQUAL(controlword::kEnableOperation, controlwordTowardsEnabled(PowerState::kSwitchedOn));
    LONGS_EQUAL(controlword::kEnableOperation, controlwordTowardsEnabled(PowerState::kOperationEnabled));
    LONGS_EQUAL(controlword::kDisableVoltage, controlwordTowardsEnabled(PowerState::kFault));
    LONGS_EQUAL(controlword::kDisableVoltage, controlwordTowardsEnabled(PowerState::kQuickStopActive));
}

// The hidden-rock sweep's metres between test_lockstep_hidden_rock.cpp's
// every fourth (3-5, 7-9, 11-13, 15-17): host only (SUITE_HOST_ONLY_system_lockstep),
// twelve more whole missions that would add about 35 s a target under
// qemu-user for what the planners answer the same way there.
#include "unit_test/system/lockstep/hidden_rock_runs.hpp"

using namespace rse::test::hidden_rock;

TEST_GROUP(LockstepHiddenRockSweep) {};

TEST(LockstepHiddenRockSweep, ARockOnTheRouteAtTheMetresBetweenIsPassedAndTheGoalReached) {
    sweep({3, 4, 5, 7, 8, 9, 11, 12, 13, 15, 16, 17});
}

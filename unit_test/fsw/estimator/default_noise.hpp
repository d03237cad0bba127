// The process noise of the default ESTIMATOR_NOISE table (tables/estimator_noise.toml),
// so the filter tests run with the noise the flight software flies.
#pragma once

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/estimator/pose_estimator_task.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::test {

inline estimator::PoseProcessNoise defaultTableNoise() {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    tables::TableService service{events};
    (void)service.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount);
    return estimator::processNoiseFrom(service.estimatorNoise());
}

}  // namespace rse::test

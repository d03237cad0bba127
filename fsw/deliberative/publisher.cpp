#include "fsw/deliberative/publisher.hpp"

#include "fsw/deliberative/deliberative_events.hpp"

namespace rse::deliberative {

void Publisher::published(core::Status status, const char* what) {
    if (core::isOk(status)) {
        return;
    }
    ++failures_;
    if (core::isReportableOccurrence(failures_)) {
        events_.report(events::kPublishFailed, core::Severity::kError, "deliberative: %s not published (%s), %u so far",
                       what, core::toString(status), static_cast<unsigned>(failures_));
    }
}

}  // namespace rse::deliberative

// Activity lines (plan_text_parser.hpp):
//
//     activity NAME KIND FROM TO [LB, UB] [cost C] [at X Y [within R]] [target N]
//              [ask COND]... [tell COND]... [when C.O]
//
// each kind with its own fields: a drive needs `at X Y` (`within R` right
// after it makes it a region), a sample, image or dig needs `target N`; a
// field given twice, or one the kind does not take, is unexpected.
#include <cstring>

#include "fsw/msg/goal_msgs.hpp"
#include "fsw/plan_executive/plan_text_parser.hpp"

namespace rse::plan_executive::plan_text {

namespace {

constexpr double kMaxCoordinateM = 100000.0;
// A drive's region, `within R`: at least 1 mm (the text's resolution; R = 0
// would be the point, written without `within`), at most the bus goal's limit.
constexpr double kMinRadiusM = 0.001;
constexpr double kMaxRadiusM = static_cast<double>(msg::kMaxGoalRadiusM);
static_assert(kMaxRadiusM * 1000.0 <= 65535.0, "Activity::radiusMm holds the largest radius in mm");

bool isFieldKeyword(const Token& t) {
    return equals(t, "cost") || equals(t, "at") || equals(t, "target") || equals(t, "ask") || equals(t, "tell") ||
           equals(t, "when");
}

}  // namespace

bool Parser::activityLine() {
    // activity NAME KIND FROM TO [ LB , UB ] fields...
    if (count_ < 10) {
        return fail(PlanError::kMissingField, &tokens_[count_ - 1]);
    }
    if (tpn_->activityCount == kMaxActivities) {
        return fail(PlanError::kTooManyActivities, &tokens_[1]);
    }
    Activity& a = tpn_->activities[tpn_->activityCount];
    a = Activity{};
    if (!activityHead(&a) || !activityFields(&a) || !guardValid(a.guard, a.from, a.to)) {
        return false;
    }
    ++tpn_->activityCount;
    return true;
}

// NAME KIND FROM TO [LB, UB]: tokens 1 .. 9.
bool Parser::activityHead(Activity* a) {
    if (!name(tokens_[1], a->name, true)) {
        return false;
    }
    for (std::uint16_t i = 0; i < tpn_->activityCount; ++i) {
        if (std::strcmp(tpn_->activities[i].name, a->name) == 0) {
            return fail(PlanError::kDuplicateName, &tokens_[1]);
        }
    }
    bool known = false;
    for (std::uint8_t k = 0; k < kActivityKindCount; ++k) {
        if (equals(tokens_[2], toString(static_cast<ActivityKind>(k)))) {
            a->kind = static_cast<ActivityKind>(k);
            known = true;
        }
    }
    if (!known) {
        return fail(PlanError::kUnknownActivityKind, &tokens_[2]);
    }
    if (!eventRef(tokens_[3], &a->from) || !eventRef(tokens_[4], &a->to)) {
        return false;
    }
    if (a->from == a->to) {
        return fail(PlanError::kSelfLoop, &tokens_[4]);
    }
    return boundsAt(5, &a->duration);
}

// The fields from token 10 on, each at most once (asks and tells up to their
// limits), and the ones the kind needs.
bool Parser::activityFields(Activity* a) {
    bool sawCost = false, sawAt = false, sawTarget = false, sawWhen = false;
    std::size_t k = 10;
    while (k < count_) {
        const Token& t = tokens_[k];
        const bool hasNext = k + 1 < count_;
        bool ok = true;
        if (equals(t, "cost") && !sawCost && hasNext) {
            ok = decimal(tokens_[k + 1], 6, 0.0, kMaxCost, &a->cost);
            sawCost = true;
            k += 2;
        } else if (equals(t, "at") && !sawAt && a->kind == ActivityKind::kDrive && k + 2 < count_) {
            ok = driveAt(&k, a);
            sawAt = true;
        } else if (equals(t, "target") && !sawTarget && hasNext && isScience(a->kind)) {
            double id = 0.0;
            ok = decimal(tokens_[k + 1], 0, 1.0, 255.0, &id);
            a->target = static_cast<std::uint8_t>(id);
            sawTarget = true;
            k += 2;
        } else if ((equals(t, "ask") || equals(t, "tell")) && hasNext) {
            ok = conditionField(&k, a);
        } else if (equals(t, "when") && !sawWhen) {
            ok = guardAt(k, &a->guard);
            sawWhen = true;
            k += 2;
        } else {
            // A keyword at the end is a field without its value; anything else is unexpected.
            return fail(hasNext || !isFieldKeyword(t) ? PlanError::kUnexpectedToken : PlanError::kMissingField, &t);
        }
        if (!ok) {
            return false;
        }
    }
    if (a->kind == ActivityKind::kDrive && !sawAt) {
        return fail(PlanError::kMissingField, &tokens_[2]);
    }
    if (isScience(a->kind) && !sawTarget) {
        return fail(PlanError::kMissingField, &tokens_[2]);
    }
    return true;
}

// `at X Y [within R]` at tokens *k ..; *k moves past it.
bool Parser::driveAt(std::size_t* k, Activity* a) {
    const std::size_t at = *k;
    if (!decimal(tokens_[at + 1], 3, -kMaxCoordinateM, kMaxCoordinateM, &a->x) ||
        !decimal(tokens_[at + 2], 3, -kMaxCoordinateM, kMaxCoordinateM, &a->y)) {
        return false;
    }
    *k = at + 3;
    // `within R`: the drive is done anywhere within R m of the point (the
    // deliberative and habitual layers stop on the way in). A bare number
    // after the point is refused, not read as a radius: it was one once,
    // with nothing to keep it.
    if (*k < count_ && equals(tokens_[*k], "within")) {
        double radiusM = 0.0;
        if (*k + 1 >= count_) {
            return fail(PlanError::kMissingField, &tokens_[*k]);
        }
        if (!decimal(tokens_[*k + 1], 3, kMinRadiusM, kMaxRadiusM, &radiusM)) {
            return false;
        }
        // decimal() read at most 3 fractional digits: whole mm up to rounding.
        a->radiusMm = static_cast<std::uint16_t>(radiusM * 1000.0 + 0.5);
        *k += 2;
    } else if (*k < count_ && looksNumeric(tokens_[*k])) {
        return fail(PlanError::kRadiusWithoutWithin, &tokens_[*k]);
    }
    return true;
}

// `ask COND` or `tell COND` at tokens *k ..; *k moves past it.
bool Parser::conditionField(std::size_t* k, Activity* a) {
    const bool tell = equals(tokens_[*k], "tell");
    std::uint8_t& count = tell ? a->tellCount : a->askCount;
    if (count == (tell ? kMaxTells : kMaxAsks)) {
        return fail(PlanError::kTooManyConditions, &tokens_[*k + 1]);
    }
    std::size_t used = 0;
    if (!conditionAt(*k + 1, tell, tell ? &a->tells[count] : &a->asks[count], &used)) {
        return false;
    }
    ++count;
    *k += 1 + used;
    return true;
}

}  // namespace rse::plan_executive::plan_text

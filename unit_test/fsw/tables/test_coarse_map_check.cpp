// The coarse map's content rules (fsw/tables/coarse_map_check.hpp): a bad map is
// refused by the image check the ground compiler and the table service share,
// naming the element at fault, and the service keeps the active map.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/tables/table_events.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/fsw/tables/table_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::tables;
using rse::test::defaultImage;

namespace {

CoarseMapTable defaultMap() {
    const std::vector<std::uint8_t> image = defaultImage(TableId::kCoarseMap);
    CoarseMapTable map{};
    CHECK_TRUE(decodeTable(image.data(), image.size(), &map).ok());
    return map;
}

std::vector<std::uint8_t> imageOf(const CoarseMapTable& map) {
    std::vector<std::uint8_t> image(kMaxTableImageSize);
    image.resize(encodeTable(map, 2, image.data(), image.size()));
    return image;
}

TableCheck check(const CoarseMapTable& map) {
    const std::vector<std::uint8_t> image = imageOf(map);
    return checkTableImage(image.data(), image.size(), TableId::kCoarseMap);
}

void setSquare(CoarseMapTable* map, int slot, float x, float y, float side) {
    const float xs[4] = {x, x + side, x + side, x};
    const float ys[4] = {y, y, y + side, y + side};
    map->vertex_count[slot] = 4;
    for (int j = 0; j < 8; ++j) {
        map->vertex_x_m[slot * 8 + j] = j < 4 ? xs[j] : 0.0F;
        map->vertex_y_m[slot * 8 + j] = j < 4 ? ys[j] : 0.0F;
    }
}

void expectInconsistent(const TableCheck& c, CoarseMapField::Index field, unsigned element) {
    CHECK_TRUE(TableReject::kInconsistent == c.reason);
    LONGS_EQUAL(field, c.field);
    LONGS_EQUAL(element, c.element);
}

}  // namespace

TEST_GROUP(CoarseMapCheck){};

TEST(CoarseMapCheck, TheDefaultMapAndBothWindingsPass) {
    CoarseMapTable map = defaultMap();
    CHECK_TRUE(map.obstacle_count >= 1);
    CHECK_TRUE(check(map).ok());
    // Clockwise: the same square with its vertices reversed.
    setSquare(&map, 0, 1.0F, 1.0F, 2.0F);
    for (int j = 0; j < 2; ++j) {
        std::swap(map.vertex_x_m[j], map.vertex_x_m[3 - j]);
        std::swap(map.vertex_y_m[j], map.vertex_y_m[3 - j]);
    }
    CHECK_TRUE(check(map).ok());
}

TEST(CoarseMapCheck, ANonConvexPolygonIsRefusedNamingItsVertex) {
    CoarseMapTable map = defaultMap();
    setSquare(&map, 1, 0.0F, 0.0F, 2.0F);
    map.vertex_count[1] = 5;  // a dent: (1, 1) between (0, 2) and (0, 0) makes a reflex corner
    map.vertex_x_m[8 + 4] = 1.0F;
    map.vertex_y_m[8 + 4] = 1.0F;
    expectInconsistent(check(map), CoarseMapField::vertex_x_m, 8 + 4);
}

// Every turn of a pentagram (a regular pentagon's vertices taken every second
// one) has the same sign, but it winds twice round: its faces bound only the
// small pentagon inside, so a planner would take the rock for much less than it
// is. Refused, naming a vertex on the wrong side of an edge.
TEST(CoarseMapCheck, APolygonThatWindsTwiceIsRefused) {
    CoarseMapTable map = defaultMap();
    map.vertex_count[0] = 5;
    for (int j = 0; j < 8; ++j) {
        const double a = 2.0 * M_PI * static_cast<double>((2 * j) % 5) / 5.0;
        map.vertex_x_m[j] = j < 5 ? static_cast<float>(10.0 + 2.0 * std::cos(a)) : 0.0F;
        map.vertex_y_m[j] = j < 5 ? static_cast<float>(2.0 * std::sin(a)) : 0.0F;
    }
    const TableCheck c = check(map);
    CHECK_TRUE(TableReject::kInconsistent == c.reason);
    LONGS_EQUAL(CoarseMapField::vertex_x_m, c.field);
    CHECK(c.element < 5);
    // The same five vertices in pentagon order pass.
    for (int j = 0; j < 5; ++j) {
        const double a = 2.0 * M_PI * static_cast<double>(j) / 5.0;
        map.vertex_x_m[j] = static_cast<float>(10.0 + 2.0 * std::cos(a));
        map.vertex_y_m[j] = static_cast<float>(2.0 * std::sin(a));
    }
    CHECK_TRUE(check(map).ok());
}

TEST(CoarseMapCheck, StraightOrRepeatedVerticesAreRefused) {
    CoarseMapTable map = defaultMap();
    setSquare(&map, 0, 0.0F, 0.0F, 2.0F);
    map.vertex_x_m[1] = 1.0F;  // (0,0) (1,0)->(2,2)? make three collinear: (0,0) (1,0) (2,0)
    map.vertex_y_m[1] = 0.0F;
    map.vertex_x_m[2] = 2.0F;
    map.vertex_y_m[2] = 0.0F;
    CHECK_TRUE(TableReject::kInconsistent == check(map).reason);
    map = defaultMap();
    setSquare(&map, 0, 0.0F, 0.0F, 2.0F);
    map.vertex_x_m[1] = map.vertex_x_m[0];  // a vertex repeated: a zero-length edge
    map.vertex_y_m[1] = map.vertex_y_m[0];
    CHECK_TRUE(TableReject::kInconsistent == check(map).reason);
}

TEST(CoarseMapCheck, VertexCountsMustMatchTheSlotsInUse) {
    CoarseMapTable map = defaultMap();
    const unsigned used = map.obstacle_count;
    map.vertex_count[0] = 2;  // too few for a polygon
    expectInconsistent(check(map), CoarseMapField::vertex_count, 0);
    map = defaultMap();
    map.vertex_count[used] = 3;  // a slot beyond obstacle_count claims vertices
    expectInconsistent(check(map), CoarseMapField::vertex_count, used);
    map = defaultMap();
    map.obstacle_count = static_cast<std::uint8_t>(used + 1);  // a slot in use with no vertices
    expectInconsistent(check(map), CoarseMapField::vertex_count, used);
}

TEST(CoarseMapCheck, LeftoverVerticesBeyondAPolygonAreRefused) {
    CoarseMapTable map = defaultMap();
    const unsigned n = map.vertex_count[0];
    map.vertex_y_m[n] = 4.0F;  // element after the last vertex of slot 0
    expectInconsistent(check(map), CoarseMapField::vertex_y_m, n);
    map = defaultMap();
    map.vertex_x_m[8 * 15 + 2] = 1.0F;  // an unused slot holding a stale vertex
    expectInconsistent(check(map), CoarseMapField::vertex_x_m, 8 * 15 + 2);
}

TEST(CoarseMapCheck, SwappedBoundsAreRefusedByTheirRule) {
    CoarseMapTable map = defaultMap();
    std::swap(map.x_min_m, map.x_max_m);
    expectInconsistent(check(map), CoarseMapField::x_min_m, 0);
}

TEST(CoarseMapCheck, TheServiceRefusesABadMapAndKeepsTheActiveOne) {
    rse::core::VirtualClock clock{0};
    rse::core::EventLog log{clock};
    TableService service{log};
    CHECK_TRUE(rse::core::Status::kOk == service.init(kDefaultTableImages, kDefaultTableImageCount));
    (void)rse::test::drainEvents(log, 0);
    const CoarseMapTable before = service.coarseMap();
    CoarseMapTable bad = before;
    setSquare(&bad, 0, 0.0F, 0.0F, 2.0F);
    bad.vertex_x_m[2] = 1.0F;  // (2,2) pulled in to (1,0.5): a reflex corner
    bad.vertex_y_m[2] = 0.5F;
    const std::vector<std::uint8_t> image = imageOf(bad);
    CHECK_TRUE(service.loadChunk(TableId::kCoarseMap, 0, image.data(), image.size()).ok());
    const TableCheck verdict = service.validate(TableId::kCoarseMap);
    CHECK_TRUE(TableReject::kInconsistent == verdict.reason);
    const auto d = rse::test::drainEvents(log, events::rejectEventId(TableReject::kInconsistent));
    LONGS_EQUAL(1, d.count);
    CHECK_TEXT(d.text.find("COARSE_MAP") != std::string::npos, d.text.c_str());
    CHECK_TEXT(d.text.find("vertex_x_m[") != std::string::npos, d.text.c_str());
    MEMCMP_EQUAL(&before, &service.coarseMap(), sizeof before);
}

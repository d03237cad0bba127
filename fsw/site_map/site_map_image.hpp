// The site map image: the orbital map product of a whole site (issue 31) as
// the ground builds it and uplinks it in chunks (docs/site_map.md). Unlike the
// 16-rock COARSE_MAP table (512 bytes) it holds up to kMaxSiteRocks rocks and
// kMaxKeepOuts keep-out zones over a site of up to kMaxSiteExtentM a side.
//
// Layout (big-endian, as everything on the ground link):
//   header, kSiteMapHeaderSize bytes:
//     u32 magic kSiteMapMagic ("RSEM")   u16 version kSiteMapVersion   u16 flags (0)
//     f32 x_min, y_min, x_max, y_max (m, site frame)
//     u32 rock_count                      u16 keep_out_count            u16 reserved (0)
//   rock_count rocks:      u8 vertex_count (3 .. 8), then vertex_count x (f32 x, f32 y)
//   keep_out_count zones:  u8 kind (KeepOutKind), u8 vertex_count (3 .. 16), then the vertices
// and nothing after. Every polygon is convex, counter-clockwise (positive
// area, every turn strictly left) and inside the site.
//
// checkSiteMapImage() is the whole validation: a map the store loads has
// passed it, so SiteMap::load() cannot fail on content. SiteMapImageCheck is
// the same check in steps of a bounded number of records (MAP_COMMIT runs it
// a slice a command-task run). Pure; no allocation.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/byte_codec.hpp"

namespace rse::site_map {

constexpr std::uint32_t kSiteMapMagic = 0x5253454DU;  // "RSEM"
constexpr std::uint16_t kSiteMapVersion = 1;
constexpr std::size_t kSiteMapHeaderSize = 32;

// 20 480: the growth table goes to 20 000 rocks on a square kilometre
// (a k = 0.30 field counted down to 1 m, bench_global_route; Snowdrift's
// k = 0.10 has about 3 200 a square kilometre).
constexpr std::size_t kMaxSiteRocks = 20480;
constexpr std::size_t kMaxRockVertices = 8;
constexpr std::size_t kMaxKeepOuts = 64;
constexpr std::size_t kMaxKeepOutVertices = 16;
// The longest side of a site (m): 2 km, so a 1 km x 1 km site fits with room.
constexpr double kMaxSiteExtentM = 2048.0;

// The largest image: every rock and zone at its most vertices.
constexpr std::size_t kMaxSiteMapImageSize = kSiteMapHeaderSize + kMaxSiteRocks * (1 + 8 * kMaxRockVertices) +
                                             kMaxKeepOuts * (2 + 8 * kMaxKeepOutVertices);

enum class KeepOutKind : std::uint8_t {
    kSteep = 1,  // slope beyond what the rover climbs
    kSoft = 2,   // soft ground (sand, a drift)
};

// Why an image was refused; kOk when it passed.
enum class SiteMapReject : std::uint8_t {
    kOk = 0,
    kTooShort,         // ends inside the header or a record
    kBadMagic,         // not a site map image
    kBadVersion,       // a version this software does not read
    kBadSite,          // site bounds not finite, empty, or beyond kMaxSiteExtentM
    kTooManyRocks,     // rock_count above kMaxSiteRocks
    kTooManyKeepOuts,  // keep_out_count above kMaxKeepOuts
    kBadVertexCount,   // a polygon with fewer than 3 or more than its maximum vertices
    kNotFinite,        // a vertex not finite
    kOutsideSite,      // a vertex outside the site bounds
    kClockwise,        // a polygon wound clockwise (or with no area)
    kNotConvex,        // a reflex or straight corner, or a boundary winding more than once
    kBadKind,          // a keep-out kind not in KeepOutKind
    kTrailingBytes,    // bytes after the last record
    kIndexFull,        // the rocks cover more grid cells than the index holds (SiteMap::kMaxCellRefs)
    kBadHeader,        // the header's flags or reserved field not 0 (a newer writer's meaning this reader lacks)
};
const char* toString(SiteMapReject reason);

struct SiteMapCheck {
    SiteMapReject reason = SiteMapReject::kOk;
    std::uint32_t item = 0;      // the rock (or zone, for zone reasons) the reason is about
    bool keepOut = false;        // item is a keep-out zone
    std::uint32_t rocks = 0;     // rock_count of a header that read
    std::uint16_t keepOuts = 0;
    bool ok() const { return reason == SiteMapReject::kOk; }
};

// The site's bounds as the header gives them.
struct SiteBounds {
    float xMin = 0.0F, yMin = 0.0F, xMax = 0.0F, yMax = 0.0F;
};

SiteMapCheck checkSiteMapImage(const std::uint8_t* image, std::size_t length);

// checkSiteMapImage in steps: begin() reads the header, each step() checks up
// to maxRecords more rocks or zones, and the verdict is the same, record for
// record, as the whole check's. The image must stay as it is until ended().
class SiteMapImageCheck {
public:
    // Starts a check of image (length bytes): the header read and checked.
    void begin(const std::uint8_t* image, std::size_t length);
    // Up to maxRecords more records (at least 1); true when the check has
    // ended (result() is the verdict).
    bool step(std::size_t maxRecords);
    bool ended() const { return ended_; }
    const SiteMapCheck& result() const { return check_; }
    // Records checked so far (rocks, then zones).
    std::size_t recordsChecked() const { return next_; }

private:
    bool fail(SiteMapReject reason);

    core::BeReader in_{nullptr, 0};
    SiteMapCheck check_{SiteMapReject::kTooShort};   // nothing checked is no pass
    SiteBounds site_{};
    std::size_t next_ = 0;       // the next record: rocks first, then zones
    std::size_t cellRefs_ = 0;   // index references the rocks so far take
    bool ended_ = true;
};

// A convex counter-clockwise polygon (exactly the image's rule): false for
// fewer than 3 vertices, a clockwise or zero-area one (*clockwise set), a
// reflex or straight corner, or one winding more than once.
bool convexCounterClockwise(const float* x, const float* y, std::size_t count, bool* clockwise);

}  // namespace rse::site_map

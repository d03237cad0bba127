// Line-of-sight shortcutting of a planned path on the local map, and the cut
// that ends a path where it enters a goal region.
//
// Greedy: from the current point, jump to the farthest later point that is in
// straight sight (segmentFree), keep it, repeat from there. Every kept segment
// is either checked free or an original segment, and a straight segment is
// never longer than the part of the path it replaces (triangle inequality), so
// the result never leaves free space the input kept to and is never longer.
// Cost: at most count * (count - 1) / 2 segment checks. RRT* paths on the
// benchmark maps have 14..65 points and shortcut in 1..25 us on the development
// host; the loops are bounded by kMaxShortcutPoints (the longest path the RRT*
// pool can hold).
#pragma once

#include <cstddef>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/habitual/rrt_star.hpp"

namespace rse::habitual {

constexpr std::size_t kMaxShortcutPoints = kMaxRrtNodes + 1;

// Sum of the segment lengths of path[0..count); 0 for fewer than two points.
double pathLength(const geometry::Point2* path, std::size_t count);

// Shortcuts path[0..count) in place and returns the new count (first and last
// points kept). count < 3 or > kMaxShortcutPoints is returned unchanged; a
// null path gives 0.
std::size_t shortcutPath(const LocalMap& map, geometry::Point2* path, std::size_t count);

// Ends path[0..count) where it first comes within radiusM of centre: the
// point where it enters that disc, on the first segment that reaches it,
// becomes the last point; returns the new count (a goal region: the rover
// stops on the way in, not at the centre). The cut path is a prefix of the
// input, so it keeps to the free space the input kept to and is never longer.
// Unchanged (count returned): radiusM not > 0, a path that starts inside the
// disc or never enters it, fewer than two points. A null path gives 0.
std::size_t cutPathAtDisc(geometry::Point2* path, std::size_t count, geometry::Point2 centre, double radiusM);

}  // namespace rse::habitual

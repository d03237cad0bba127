// The Monte Carlo checker (unit_test/bench/cc_monte_carlo.hpp) against cases
// with a known answer: no noise (0 or 1, segment against waypoint counts), a
// wall parallel to a straight path (closed form for one step, a numerical
// recursion for several), and the binomial upper bounds.
#include <cmath>
#include <cstdint>
#include <vector>

#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"
#include "unit_test/bench/cc_monte_carlo.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::test::cc;

namespace {

constexpr std::size_t kSamples = 100000;

CcProblem straightProblem(std::uint8_t steps, double startSd, double sigma) {
    CcProblem p;
    p.steps = steps;
    p.startX = 0.0;
    p.startY = 0.0;
    p.goalX = 10.0;
    p.goalY = 0.0;
    p.startCov[0] = startSd * startSd;
    p.startCov[3] = startSd * startSd;
    p.processSigmaM = sigma;
    p.xMin = -200.0;
    p.xMax = 200.0;
    p.yMin = -200.0;
    p.yMax = 200.0;
    p.riskBound = 0.05;
    return p;
}

// Means evenly along (0, 0) -> (10, 0).
void straightMeans(std::size_t steps, double* x, double* y) {
    for (std::size_t t = 0; t <= steps; ++t) {
        x[t] = 10.0 * static_cast<double>(t) / static_cast<double>(steps);
        y[t] = 0.0;
    }
}

// A wall y >= d across the whole path (a box far larger than the path).
PlanObstacle wall(double d) { return boxObstacle(-100.0, d, 100.0, 150.0, 1); }

// One noisy step (sd 0.3 m at the start, 0.3 m per step) along y = 0 with the
// wall y >= d beside it.
CcProblem oneStepBesideWall(double d) {
    CcProblem p = straightProblem(1, 0.3, 0.3);
    p.obstacleCount = 1;
    p.obstacles[0] = wall(d);
    return p;
}

double phi(double x) { return std::exp(-0.5 * x * x) / std::sqrt(2.0 * 3.14159265358979323846); }

// P(max_t y_t > d) for y_0 ~ N(0, s0^2), y_{t+1} = y_t + N(0, sigma^2), t < steps:
// the density of the paths that have not crossed, propagated on a grid.
double wallCrossingProbability(double d, double s0, double sigma, std::size_t steps) {
    const double lo = -8.0 * std::sqrt(s0 * s0 + static_cast<double>(steps) * sigma * sigma);
    const std::size_t cells = 800;
    const double h = (d - lo) / static_cast<double>(cells);
    std::vector<double> f(cells + 1), g(cells + 1);
    for (std::size_t k = 0; k <= cells; ++k) {
        f[k] = phi((lo + h * static_cast<double>(k)) / s0) / s0;
    }
    auto mass = [&](const std::vector<double>& v) {  // trapezoid
        double m = 0.0;
        for (std::size_t k = 0; k < cells; ++k) {
            m += 0.5 * h * (v[k] + v[k + 1]);
        }
        return m;
    };
    for (std::size_t t = 0; t < steps; ++t) {
        for (std::size_t k = 0; k <= cells; ++k) {
            const double y = lo + h * static_cast<double>(k);
            double acc = 0.0;
            for (std::size_t u = 0; u <= cells; ++u) {
                const double w = (u == 0 || u == cells) ? 0.5 : 1.0;
                acc += w * f[u] * phi((y - (lo + h * static_cast<double>(u))) / sigma) / sigma;
            }
            g[k] = acc * h;
        }
        f.swap(g);
    }
    return 1.0 - mass(f);
}

// |empirical - expected| within 5 binomial standard deviations.
void checkRate(double expected, const McResult& r) {
    const double sd = std::sqrt(expected * (1.0 - expected) / static_cast<double>(r.samples));
    DOUBLES_EQUAL(expected, r.rate, 5.0 * sd + 1e-12);
}

}  // namespace

TEST_GROUP(CcMonteCarlo){};

TEST(CcMonteCarlo, WithoutNoiseTheMeanPathDecidesAndOnlySegmentsSeeTheCornerCut) {
    CcProblem p = straightProblem(1, 0.0, 0.0);
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(4.0, -1.0, 6.0, 1.0, 1);
    double x[3], y[3];
    straightMeans(1, x, y);
    McOptions small;
    small.samples = 2000;
    // One step straight through the box: every trajectory, no waypoint inside.
    McResult r = monteCarloCollision(p, x, y, small);
    LONGS_EQUAL(2000, r.collisions);
    LONGS_EQUAL(0, r.waypointCollisions);
    LONGS_EQUAL(2000, r.collisionsPerObstacle[0]);
    DOUBLES_EQUAL(1.0, r.rate, 0.0);
    DOUBLES_EQUAL(1.0, r.upperClopperPearson, 0.0);
    // Two steps with the middle mean in the box: the waypoint count sees it too.
    p.steps = 2;
    straightMeans(2, x, y);
    r = monteCarloCollision(p, x, y, small);
    LONGS_EQUAL(2000, r.collisions);
    LONGS_EQUAL(2000, r.waypointCollisions);
    // Around the box, touching its faces: nothing; the bound is then 1 - 0.05^(1/n).
    p.steps = 3;
    const double ax[] = {0.0, 4.0, 6.0, 10.0}, ay[] = {0.0, 1.0, 1.0, 0.0};
    r = monteCarloCollision(p, ax, ay, small);
    LONGS_EQUAL(0, r.collisions);
    DOUBLES_EQUAL(0.0, r.rate, 0.0);
    DOUBLES_EQUAL(1.0 - std::pow(0.05, 1.0 / 2000.0), r.upperClopperPearson, 1e-12);
    // Every mean outside, but the step (3.5, 0.4) -> (4.6, 1.5) cuts the corner (4, 1).
    p.steps = 4;
    const double cx[] = {0.0, 3.5, 4.6, 6.5, 10.0}, cy[] = {0.0, 0.4, 1.5, 1.5, 0.0};
    r = monteCarloCollision(p, cx, cy, small);
    LONGS_EQUAL(2000, r.collisions);
    LONGS_EQUAL(0, r.waypointCollisions);
}

TEST(CcMonteCarlo, OneStepBesideAWallMatchesTheClosedForms) {
    double x[2], y[2];
    straightMeans(1, x, y);
    // Start known exactly, process noise only: P = P(y_1 > d) = 1 - Phi(d / sigma).
    CcProblem p = straightProblem(1, 0.0, 0.5);
    p.obstacleCount = 1;
    p.obstacles[0] = wall(0.8);
    McResult r = monteCarloCollision(p, x, y);
    LONGS_EQUAL(kSamples, r.samples);
    checkRate(1.0 - normalCdf(0.8 / 0.5), r);
    // A half-plane is met by a segment iff by one of its ends: same counts.
    LONGS_EQUAL(r.collisions, r.waypointCollisions);
    CHECK(r.upperClopperPearson > r.rate);
    CHECK(r.upperWilson > r.rate);

    // Start uncertainty only: both ends move together, P = 1 - Phi(d / s0).
    p = straightProblem(1, 0.4, 0.0);
    p.obstacleCount = 1;
    p.obstacles[0] = wall(0.8);
    checkRate(1.0 - normalCdf(0.8 / 0.4), monteCarloCollision(p, x, y));

    // Both: P = 1 - int_{y < d} N(y; 0, s0^2) Phi((d - y) / sigma) dy (Simpson).
    const double s0 = 0.3, sigma = 0.3, d = 0.6;
    p = straightProblem(1, s0, sigma);
    p.obstacleCount = 1;
    p.obstacles[0] = wall(d);
    const double lo = -10.0 * s0;
    const int n = 4000;
    const double h = (d - lo) / n;
    double integral = 0.0;
    for (int k = 0; k <= n; ++k) {
        const double yy = lo + h * k;
        const double w = (k == 0 || k == n) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
        integral += w * phi(yy / s0) / s0 * normalCdf((d - yy) / sigma);
    }
    const double expected = 1.0 - integral * h / 3.0;
    DOUBLES_EQUAL(expected, wallCrossingProbability(d, s0, sigma, 1), 2e-5);
    checkRate(expected, monteCarloCollision(p, x, y));
}

TEST(CcMonteCarlo, SeveralStepsBesideAWallMatchTheDensityRecursion) {
    const std::uint8_t steps = 5;
    double x[6], y[6];
    straightMeans(steps, x, y);
    CcProblem p = straightProblem(steps, 0.1, 0.2);
    p.obstacleCount = 2;
    p.obstacles[0] = wall(0.5);
    p.obstacles[1] = boxObstacle(-100.0, -150.0, 100.0, -50.0, 2);  // far below: never met
    const double expected = wallCrossingProbability(0.5, 0.1, 0.2, steps);
    CHECK(expected > 0.05 && expected < 0.5);
    const McResult r = monteCarloCollision(p, x, y);
    checkRate(expected, r);
    LONGS_EQUAL(r.collisions, r.collisionsPerObstacle[0]);
    LONGS_EQUAL(0, r.collisionsPerObstacle[1]);
    // The plan overload samples the same.
    CcPlan plan;
    plan.steps = steps;
    for (std::size_t t = 0; t <= steps; ++t) {
        plan.meanX[t] = x[t];
        plan.meanY[t] = y[t];
    }
    LONGS_EQUAL(r.collisions, monteCarloCollision(p, plan).collisions);
}

TEST(CcMonteCarlo, SeededAndRepeatable) {
    double x[2], y[2];
    straightMeans(1, x, y);
    CcProblem p = oneStepBesideWall(0.6);
    McOptions a;
    a.seed = 7;
    McOptions b = a;
    b.seed = 8;
    const McResult first = monteCarloCollision(p, x, y, a);
    LONGS_EQUAL(first.collisions, monteCarloCollision(p, x, y, a).collisions);
    CHECK(first.collisions != monteCarloCollision(p, x, y, b).collisions);
}

TEST(CcMonteCarlo, BinomialUpperBounds) {
    // k = 0: P(X = 0) = (1 - p)^n = alpha exactly.
    DOUBLES_EQUAL(1.0 - std::pow(0.05, 1e-5), clopperPearsonUpper(0, 100000), 1e-12);
    DOUBLES_EQUAL(1.0, clopperPearsonUpper(10, 10), 0.0);
    // The bound is where the binomial CDF falls to 1 - confidence.
    for (std::size_t k : {1u, 17u, 250u, 999u}) {
        const double u = clopperPearsonUpper(k, 1000, 0.95);
        CHECK(u > static_cast<double>(k) / 1000.0);
        DOUBLES_EQUAL(0.05, binomialCdf(k, 1000, u), 1e-9);
        CHECK(clopperPearsonUpper(k, 1000, 0.99) > u);
        CHECK(wilsonUpper(k, 1000) > static_cast<double>(k) / 1000.0);
    }
    // CDF against a direct sum.
    double direct = 0.0;
    for (int j = 0; j <= 3; ++j) {
        direct += std::exp(std::lgamma(21.0) - std::lgamma(j + 1.0) - std::lgamma(21.0 - j) + j * std::log(0.1) +
                           (20 - j) * std::log(0.9));
    }
    DOUBLES_EQUAL(direct, binomialCdf(3, 20, 0.1), 1e-12);
    // Wilson with k = 0: z^2 / (n + z^2).
    const double z = normalQuantile(0.95);
    DOUBLES_EQUAL(z * z / (1000.0 + z * z), wilsonUpper(0, 1000), 1e-12);
}

TEST(CcMonteCarlo, SampleCountGrowsAsTheRiskBoundShrinks) {
    LONGS_EQUAL(100000, monteCarloSamples(0.05));
    LONGS_EQUAL(500000, monteCarloSamples(1e-3));
    LONGS_EQUAL(5000000, monteCarloSamples(1e-4, 1000));
    LONGS_EQUAL(2500, monteCarloSamples(0.2, 1000));
    LONGS_EQUAL(123, monteCarloSamples(0.0, 123));  // no bound to resolve: the minimum
}

TEST(CcMonteCarlo, ConservatismIsDeltaOverTheRateOrALowerBoundWithoutHits) {
    double x[2], y[2];
    straightMeans(1, x, y);
    CcProblem p = oneStepBesideWall(0.6);
    McOptions options;
    options.samples = 20000;
    const McResult hits = monteCarloCollision(p, x, y, options);
    CHECK(hits.collisions > 0);
    const Conservatism c = conservatism(0.5, hits);
    CHECK_FALSE(c.lowerBound);
    DOUBLES_EQUAL(0.5 * 20000.0 / static_cast<double>(hits.collisions), c.ratio, 1e-9);
    p = oneStepBesideWall(50.0);  // far away: no trajectory reaches it
    const McResult none = monteCarloCollision(p, x, y, options);
    LONGS_EQUAL(0, none.collisions);
    const Conservatism lower = conservatism(0.01, none);
    CHECK(lower.lowerBound);
    DOUBLES_EQUAL(0.01 / clopperPearsonUpper(0, 20000), lower.ratio, 1e-12);
}

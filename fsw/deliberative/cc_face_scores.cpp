#include "fsw/deliberative/cc_face_scores.hpp"

namespace rse::deliberative {

void chooseFacesAt(const CcProblem& problem, const CcEndMargins& margins, const double* mx, const double* my,
                   CcFaceTable& face) {
    for (std::size_t t = 0; t < problem.steps; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
            double best = -INFINITY;
            std::uint8_t bestFace = 0;
            for (std::size_t j = 0; j < problem.obstacles[i].faceCount; ++j) {
                const double s = pairScore(problem, margins, t, i, j, mx, my);
                if (s > best) {
                    best = s;
                    bestFace = static_cast<std::uint8_t>(j);
                }
            }
            face[t][i] = bestFace;
        }
    }
}

}  // namespace rse::deliberative

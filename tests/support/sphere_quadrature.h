// Integrals over the sphere of directions by the midpoint rule in (theta, phi), theta measured from +Y, with
// the solid-angle element sin(theta) dtheta dphi: brute force for closed-form checks, independent of any
// sampling density or Jacobian under test.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace vkrt::test {

// The integral of f(direction) (a double or a glm vector) over the unit sphere, on thetaSteps x phiSteps
// cells.
template <typename F>
auto integrateOverSphere(int thetaSteps, int phiSteps, const F& f) {
    decltype(f(glm::dvec3(0.0, 1.0, 0.0))) sum{};
    const double dTheta = M_PI / thetaSteps, dPhi = 2.0 * M_PI / phiSteps;
    for (int i = 0; i < thetaSteps; ++i) {
        const double theta = (i + 0.5) * dTheta;
        for (int j = 0; j < phiSteps; ++j) {
            const double phi = (j + 0.5) * dPhi;
            const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::cos(theta),
                               std::sin(theta) * std::sin(phi));
            sum += f(d) * (std::sin(theta) * dTheta * dPhi);
        }
    }
    return sum;
}

}  // namespace vkrt::test

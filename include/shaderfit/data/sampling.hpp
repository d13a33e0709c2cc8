// Where a reference is sampled: the default sample design for a domain, and denser designs that
// contain it (for checking errors between the samples, verify/worst_case.hpp). docs/reference.md
// ("Sampling") describes the designs.
//
//   std::vector<reference::DomainAxis> box = {parse_domain_axis("x=-1:1", "domain")};
//   SampleColumns s = sample_domain(box, 0);   // 10,001 points, both ends, mirrored about 0
//   SampleColumns d = sample_domain(box, 0, 10);  // 10x denser, the first design's points included
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "shaderfit/core/error.hpp"
#include "shaderfit/reference/domain.hpp"

namespace shaderfit {

// One column per axis, in axis order; every column has the same number of rows.
using SampleColumns = std::vector<std::vector<double>>;

// The most points a design may have.
inline constexpr std::size_t kMaxDesignPoints = 100'000'000;

// The points of the default design when `samples` is 0: 10,001 in one dimension, 4,096 inside
// plus the boundary in two, 8,192 inside plus the boundary in three to six.
std::size_t default_sample_count(std::size_t dimensions);

// The samples of a box (1 to 6 axes):
//  - when every axis has a count: the Cartesian product of the axes' regular grids (the first
//    axis slowest), `samples` and `density` not used;
//  - otherwise (no axis has a count) a design of `samples` (0: default_sample_count) points:
//    - in one dimension an even grid of `samples` >= 2 points from lo to hi, both ends included,
//      in increasing order; where lo = -hi its points mirror exactly about 0 (point n-1-i is
//      -(point i) bit for bit, and the middle point of an odd count is 0);
//    - in d = 2 to 6 dimensions the 2^d corners, then on each of the 2d faces (axis 0 at lo,
//      axis 0 at hi, axis 1 at lo, ...) the points 1 to m of a Sobol set of d - 1 dimensions
//      over the other axes, m = round(samples^((d-1)/d)), then the Sobol points 1 to `samples`
//      inside (point 0 of each set, a corner, is skipped): `samples` inside plus the boundary;
//  - `density` > 1 gives a design about that many times denser that holds every point of the
//    first (bit for bit): the grid with density - 1 points between neighbours, or the Sobol sets
//    continued to density times their length.
// Deterministic: no random numbers. Throws shaderfit::Error located at `where` for no axes, more
// than six without counts, some axes with counts and others without, one point in one dimension,
// a density of 0, or more than kMaxDesignPoints points.
SampleColumns sample_domain(std::span<const reference::DomainAxis> axes, std::size_t samples,
                            std::size_t density = 1, const SourceLocation& where = {"domain"});

// Point i of the Sobol sequence in [0, 1)^dimensions (1 to 8 dimensions; Joe and Kuo's
// direction numbers, new-joe-kuo-6.21201, 32 bits, in Gray-code order as scipy's and Joe and
// Kuo's own generator give it), i = 0 the origin. Throws Error for other dimensions or
// i >= 2^32.
std::vector<double> sobol_point(std::size_t dimensions, std::uint64_t i);

}  // namespace shaderfit

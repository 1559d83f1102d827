#pragma once
// The hue tests of the gather's reading of probe SH2 (SPEC §6.7): light made of white and one coloured source, which
// grey surfaces reflect each in its own hue, so that every true irradiance is a·white + b·colour with a, b ≥ 0.
#include <glm/glm.hpp>

namespace ssvgi::testing {

// The coefficients of an irradiance in the (white, colour) basis, by least squares over the three channels, and the
// part of it outside their plane.
struct WhiteAndColour {
  double white;
  double colour;
  double outside;
};

inline WhiteAndColour splitIntoWhiteAnd(glm::dvec3 colour, glm::dvec3 irradiance) {
  const glm::dvec3 white(1.0);
  const double ww = glm::dot(white, white), wc = glm::dot(white, colour), cc = glm::dot(colour, colour);
  const double we = glm::dot(white, irradiance), ce = glm::dot(colour, irradiance);
  const double determinant = ww * cc - wc * wc;
  const double a = (we * cc - ce * wc) / determinant;
  const double b = (ce * ww - we * wc) / determinant;
  return {a, b, glm::length(irradiance - a * white - b * colour)};
}

}  // namespace ssvgi::testing

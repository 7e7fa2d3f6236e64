// Host-side checks of the mixed elements.
#include <kernels/MixedElasticity.hpp>

namespace mixcon {

MassLumping massLumping(ElementType type) {
  return dispatchPlaneElement(type, "the mixed pairing",
                              [](auto elem) { return MixedTraits<decltype(elem)>::kLumping; });
}

void checkMixedPairing(ElementType displacement, ElementType stress) {
  if (spatialDimension(displacement) != 2 || spatialDimension(stress) != 2)
    throw InputError("mixed model: " + elementTypeName(displacement) + " displacements with " +
                     elementTypeName(stress) +
                     " stresses: the mixed model is 2D only so far (quadrilaterals; issue 17)");
  if (displacement == stress)
    return;
  if (displacement == ElementType::Quad8 && stress == ElementType::Quad4)
    throw InputError("mixed model: quad8 displacements with quad4 stresses violate the "
                     "Mirza-Olson completeness criterion (bilinear stresses cannot represent the "
                     "linear strain field of quadratic displacements); use quad8 stresses");
  throw InputError("mixed model: quad4 displacements with quad8 stresses give more stress than "
                   "strain modes per element (a singular saddle-point system); use quad4 "
                   "stresses (equal order)");
}

} // namespace mixcon

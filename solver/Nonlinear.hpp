// Geometrically nonlinear (updated-Lagrangian) analysis, everything at once: the problem
// interface (NonlinearModel), the two models of the report and the load-step driver.
#pragma once

#include <solver/LoadStepper.hpp>
#include <solver/NonlinearDisplacementModel.hpp>
#include <solver/NonlinearMixedModel.hpp>
#include <solver/NonlinearModel.hpp>
#include <solver/SolidNonlinearMixedModel.hpp>

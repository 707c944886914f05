// The stick flight: the shipped full-deflection recording flown by the generic profile and the
// flight model, sampled between its 1 ms steps.
#include "EvaluatedFlight.h"

#include <ig_core/SyntheticTerrain.h>

#include <fieldcast/Conventions.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace fieldcast::tools {
namespace {

TEST(StickFlight, FliesTheRecordingsFullDeflectionsThroughTheFlightModel) {
  const auto terrain = core::makeSyntheticTerrain({core::SyntheticKind::Hills, 1024, 2.0, 6, 1});
  Pose start;
  start.positionM = {1000.0, 600.0, terrain->view().heightAtM(1000.0, 600.0) + 150.0};
  const EvaluatedFlight flight = stickFlight(
      std::string(FIELDCAST_SOURCE_DIR) + "/config/flights/eval_stick_aggressive.rec", start, 150.0, terrain->view());
  EXPECT_EQ(flight.name(), "eval_stick_aggressive");
  EXPECT_NEAR(flight.durationS(), 6.0, 1e-9);
  // Centred for the first 0.6 s: straight and level from the start, at the start speed
  const Pose early = flight.poseAtSeconds(0.5);
  EXPECT_EQ(early.rollRad, 0.0);
  EXPECT_NEAR(early.positionM.y - start.positionM.y, 0.5 * 150.0, 1.0);  // heading 0 is north
  // Full right roll from 0.6 s (slammed in 40 ms) at the model's 1.5 rad/s: about 0.87 rad at 1.2 s
  EXPECT_NEAR(flight.poseAtSeconds(1.2).rollRad, 1.5 * (0.6 - 0.02), 0.03);
  // Full left roll from 1.5 s to 2.5 s undoes it and rolls on to the left
  EXPECT_LT(flight.poseAtSeconds(2.5).rollRad, -0.3);
  // Between the model's steps the pose is interpolated, not held
  const double a = flight.poseAtSeconds(0.9).rollRad, b = flight.poseAtSeconds(0.9005).rollRad,
               c = flight.poseAtSeconds(0.901).rollRad;
  EXPECT_GT(b, a);
  EXPECT_GT(c, b);
  EXPECT_THROW(stickFlight("/nonexistent.rec", start, 150.0, terrain->view()), std::runtime_error);
}

}  // namespace
}  // namespace fieldcast::tools

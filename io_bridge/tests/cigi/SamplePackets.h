#pragma once
// One packet of each kind the codec handles, every field set to a value other than its default
// (and distinct where it can be), for round trips, the tshark capture, fuzz seeds and the bench.
// Floating-point values are exact in binary and short in decimal, so a third party prints them
// back exactly.

#include <io_bridge/cigi/Packets.h>

namespace fieldcast::io::cigi::testdata {

inline IgControl sampleIgControl() {
  IgControl p;
  p.databaseNumber = 7;
  p.igMode = IgMode::Operate;
  p.timestampValid = true;
  p.extrapolationEnabled = true;
  p.hostFrameNumber = 16909060;  // 0x01020304
  p.timestampTicks = 123456789;
  p.lastIgFrameNumber = 987654;
  return p;
}

inline EntityControl sampleEntityControl() {
  EntityControl p;
  p.entityId = 42;
  p.entityState = EntityState::Active;
  p.attachState = AttachState::Attached;
  p.collisionDetectionEnabled = true;
  p.inheritAlpha = true;
  p.groundOceanClamp = GroundOceanClamp::Conformal;
  p.animationDirection = AnimationDirection::Backward;
  p.animationLoopMode = AnimationLoopMode::Continuous;
  p.animationState = AnimationState::Play;
  p.extrapolationEnabled = true;
  p.alpha = 200;
  p.entityType = 1234;
  p.parentId = 7;
  p.rollDeg = 1.5f;
  p.pitchDeg = -2.25f;
  p.yawDeg = 271.75f;
  p.latitudeDegOrXM = 37.625;
  p.longitudeDegOrYM = -122.375;
  p.altitudeMOrZM = 1234.5;
  return p;
}

inline RateControl sampleRateControl() {
  RateControl p;
  p.entityId = 42;
  p.articulatedPartId = 3;
  p.applyToArticulatedPart = true;
  p.frame = RateFrame::Local;
  p.xRateMps = 12.5f;
  p.yRateMps = -3.25f;
  p.zRateMps = 0.75f;
  p.rollRateDegps = 4.5f;
  p.pitchRateDegps = -1.125f;
  p.yawRateDegps = 9.25f;
  return p;
}

inline CelestialSphereControl sampleCelestialSphereControl() {
  CelestialSphereControl p;
  p.hour = 14;
  p.minute = 35;
  p.ephemerisModelEnabled = true;
  p.sunEnabled = true;
  p.moonEnabled = false;
  p.starFieldEnabled = true;
  p.dateTimeValid = true;
  p.dateMMDDYYYY = 6212024;
  p.starFieldIntensityPercent = 62.5f;
  return p;
}

inline AtmosphereControl sampleAtmosphereControl() {
  AtmosphereControl p;
  p.atmosphericModelEnabled = true;
  p.humidityPercent = 55;
  p.airTemperatureC = 21.5f;
  p.visibilityRangeM = 25000.0f;
  p.horizontalWindSpeedMps = 7.25f;
  p.verticalWindSpeedMps = -0.5f;
  p.windDirectionDeg = 245.5f;
  p.barometricPressureHpa = 1013.25f;
  return p;
}

inline ViewControl sampleViewControl() {
  ViewControl p;
  p.viewId = 3;
  p.groupId = 2;
  p.xOffsetEnabled = true;
  p.yOffsetEnabled = false;
  p.zOffsetEnabled = true;
  p.rollEnabled = false;
  p.pitchEnabled = true;
  p.yawEnabled = true;
  p.entityId = 5;
  p.xOffsetM = 1.25f;
  p.yOffsetM = -0.5f;
  p.zOffsetM = -1.75f;
  p.rollDeg = 2.5f;
  p.pitchDeg = -10.25f;
  p.yawDeg = 45.5f;
  return p;
}

inline ViewDefinition sampleViewDefinition() {
  ViewDefinition p;
  p.viewId = 3;
  p.groupId = 2;
  p.nearEnabled = true;
  p.farEnabled = true;
  p.leftEnabled = true;
  p.rightEnabled = false;
  p.topEnabled = true;
  p.bottomEnabled = true;
  p.mirrorMode = MirrorMode::Horizontal;
  p.pixelReplication = 1;
  p.projectionType = ProjectionType::Orthographic;
  p.reorder = true;
  p.viewType = 5;
  p.nearM = 0.25f;
  p.farM = 50000.0f;
  p.leftDeg = -30.5f;
  p.rightDeg = 32.25f;
  p.topDeg = 20.75f;
  p.bottomDeg = -18.5f;
  return p;
}

inline HatHotRequest sampleHatHotRequest() {
  HatHotRequest p;
  p.hatHotId = 77;
  p.requestType = HatHotRequestType::Extended;
  p.coordinateSystem = CoordinateSystem::Entity;
  p.updatePeriod = 2;
  p.entityId = 42;
  p.latitudeDegOrXM = 10.5;
  p.longitudeDegOrYM = -20.25;
  p.altitudeMOrZM = 300.125;
  return p;
}

inline LosSegmentRequest sampleLosSegmentRequest() {
  LosSegmentRequest p;
  p.losId = 88;
  p.requestType = LosRequestType::Extended;
  p.sourceCoordinateSystem = CoordinateSystem::Entity;
  p.destinationCoordinateSystem = CoordinateSystem::Geodetic;
  p.responseCoordinateSystem = CoordinateSystem::Entity;
  p.destinationEntityIdValid = true;
  p.alphaThreshold = 128;
  p.entityId = 42;
  p.sourceLatitudeDegOrXM = 1.5;
  p.sourceLongitudeDegOrYM = 2.5;
  p.sourceAltitudeMOrZM = -3.5;
  p.destinationLatitudeDegOrXM = 37.5;
  p.destinationLongitudeDegOrYM = -122.25;
  p.destinationAltitudeMOrZM = 150.75;
  p.materialMask = 252645135;  // 0x0F0F0F0F
  p.updatePeriod = 4;
  p.destinationEntityId = 9;
  return p;
}

inline LosVectorRequest sampleLosVectorRequest() {
  LosVectorRequest p;
  p.losId = 99;
  p.requestType = LosRequestType::Extended;
  p.sourceCoordinateSystem = CoordinateSystem::Entity;
  p.responseCoordinateSystem = CoordinateSystem::Entity;
  p.alphaThreshold = 64;
  p.entityId = 42;
  p.azimuthDeg = 123.5f;
  p.elevationDeg = -15.25f;
  p.minRangeM = 10.5f;
  p.maxRangeM = 20000.0f;
  p.sourceLatitudeDegOrXM = 0.5;
  p.sourceLongitudeDegOrYM = -1.5;
  p.sourceAltitudeMOrZM = 2.25;
  p.materialMask = 3735928559u;  // 0xDEADBEEF
  p.updatePeriod = 3;
  return p;
}

inline StartOfFrame sampleStartOfFrame() {
  StartOfFrame p;
  p.databaseNumber = -7;  // loading database 7
  p.igStatus = 2;
  p.igMode = IgMode::Operate;
  p.timestampValid = true;
  p.earthReferenceModel = EarthReferenceModel::HostDefined;
  p.igFrameNumber = 305419896;  // 0x12345678
  p.timestampTicks = 4000000000u;
  p.lastHostFrameNumber = 16909060;
  return p;
}

inline HatHotResponse sampleHatHotResponse() {
  HatHotResponse p;
  p.hatHotId = 77;
  p.valid = true;
  p.responseType = HatHotResponseType::HeightOfTerrain;
  p.hostFrameNumberLsn = 10;
  p.heightM = 512.25;
  return p;
}

inline HatHotExtendedResponse sampleHatHotExtendedResponse() {
  HatHotExtendedResponse p;
  p.hatHotId = 78;
  p.valid = true;
  p.hostFrameNumberLsn = 5;
  p.heightAboveTerrainM = 120.5;
  p.heightOfTerrainM = 480.75;
  p.materialCode = 17;
  p.normalAzimuthDeg = 33.5f;
  p.normalElevationDeg = 85.25f;
  return p;
}

inline LosResponse sampleLosResponse() {
  LosResponse p;
  p.losId = 88;
  p.valid = true;
  p.entityIdValid = true;
  p.visible = false;
  p.hostFrameNumberLsn = 12;
  p.responseCount = 2;
  p.entityId = 9;
  p.rangeM = 1500.125;
  return p;
}

inline LosExtendedResponse sampleLosExtendedResponse() {
  LosExtendedResponse p;
  p.losId = 99;
  p.valid = true;
  p.entityIdValid = false;
  p.rangeValid = true;
  p.visible = true;
  p.hostFrameNumberLsn = 3;
  p.responseCount = 1;
  p.entityId = 11;
  p.rangeM = 2500.5;
  p.latitudeDegOrXM = 37.5;
  p.longitudeDegOrYM = -122.25;
  p.altitudeMOrZM = 140.25;
  p.red = 10;
  p.green = 20;
  p.blue = 30;
  p.alpha = 255;
  p.materialCode = 4242;
  p.normalAzimuthDeg = 12.5f;
  p.normalElevationDeg = 70.75f;
  return p;
}

}  // namespace fieldcast::io::cigi::testdata

#pragma once
// CIGI 3.3 packets (SISO-STD-013) the codec reads and writes, as plain host-order values in the
// units the ICD defines: angles in degrees, distances in metres, speeds in m/s, angular rates in
// deg/s. Each struct names its opcode (kOpcode) and its fixed wire size in bytes (kSize); the
// byte layouts are written out above each encoder in io_bridge/src/cigi/Codec.cpp.
//
// Positions follow CIGI's convention: a top-level entity (or a geodetic request) is placed by
// geodetic latitude/longitude in degrees and altitude in metres above the ellipsoid (WGS 84
// unless the host defines another model); an attached entity or an entity-relative request by
// x/y/z offsets in metres in its parent's body frame (x forward, y right, z down).

#include <cstdint>
#include <variant>

namespace fieldcast::io::cigi {

/// CIGI major version this codec speaks, and the minor version it writes (3.3).
inline constexpr std::uint8_t kMajorVersion = 3;
inline constexpr std::uint8_t kMinorVersion = 3;

/// IG Control's IG Mode (host's command) and Start of Frame's IG Mode (IG's state).
enum class IgMode : std::uint8_t { ResetStandby = 0, Operate = 1, Debug = 2, OfflineMaintenance = 3 };

/// Whether a position is geodetic or relative to an entity.
enum class CoordinateSystem : std::uint8_t { Geodetic = 0, Entity = 1 };

enum class EntityState : std::uint8_t { Inactive = 0, Active = 1, Destroyed = 2 };
enum class AttachState : std::uint8_t { Detached = 0, Attached = 1 };
enum class GroundOceanClamp : std::uint8_t { None = 0, NonConformal = 1, Conformal = 2 };
enum class AnimationDirection : std::uint8_t { Forward = 0, Backward = 1 };
enum class AnimationLoopMode : std::uint8_t { OneShot = 0, Continuous = 1 };
enum class AnimationState : std::uint8_t { Stop = 0, Pause = 1, Play = 2, Continue = 3 };
/// Rate Control: rates in the parent's (world's) frame or the entity's own body frame.
enum class RateFrame : std::uint8_t { World = 0, Local = 1 };
enum class MirrorMode : std::uint8_t { None = 0, Horizontal = 1, Vertical = 2, HorizontalAndVertical = 3 };
enum class ProjectionType : std::uint8_t { Perspective = 0, Orthographic = 1 };
/// HAT/HOT Request: which answer the host wants (Extended → HAT/HOT Extended Response).
enum class HatHotRequestType : std::uint8_t { HeightAboveTerrain = 0, HeightOfTerrain = 1, Extended = 2 };
/// HAT/HOT Response: what its Height is.
enum class HatHotResponseType : std::uint8_t { HeightAboveTerrain = 0, HeightOfTerrain = 1 };
/// LOS requests: Basic → LOS Response, Extended → LOS Extended Response.
enum class LosRequestType : std::uint8_t { Basic = 0, Extended = 1 };
/// Start of Frame: WGS 84 or a host-defined Earth reference model.
enum class EarthReferenceModel : std::uint8_t { Wgs84 = 0, HostDefined = 1 };

// ---- Host → IG ---------------------------------------------------------------------------

/// IG Control (1): leads every host→IG datagram. Carries the byte-swap magic on the wire.
struct IgControl {
  static constexpr std::uint8_t kOpcode = 1;
  static constexpr std::uint8_t kSize = 24;
  std::int8_t databaseNumber = 0;  ///< 0: keep the current database; >0: load it; <0 not used by hosts
  IgMode igMode = IgMode::Operate;
  bool timestampValid = false;
  bool extrapolationEnabled = false;  ///< global dead-reckoning enable
  std::uint32_t hostFrameNumber = 0;
  std::uint32_t timestampTicks = 0;     ///< host time in 10 µs ticks
  std::uint32_t lastIgFrameNumber = 0;  ///< IG frame number of the last Start of Frame received
  bool operator==(const IgControl&) const = default;
};

/// Entity Control (2): state and pose of one entity (entity 0 is the ownship).
struct EntityControl {
  static constexpr std::uint8_t kOpcode = 2;
  static constexpr std::uint8_t kSize = 48;
  std::uint16_t entityId = 0;
  EntityState entityState = EntityState::Active;
  AttachState attachState = AttachState::Detached;
  bool collisionDetectionEnabled = false;
  bool inheritAlpha = false;
  GroundOceanClamp groundOceanClamp = GroundOceanClamp::None;
  AnimationDirection animationDirection = AnimationDirection::Forward;
  AnimationLoopMode animationLoopMode = AnimationLoopMode::OneShot;
  AnimationState animationState = AnimationState::Stop;
  bool extrapolationEnabled = false;  ///< per-entity extrapolation/interpolation (3.3)
  std::uint8_t alpha = 255;
  std::uint16_t entityType = 0;
  std::uint16_t parentId = 0;
  float rollDeg = 0;
  float pitchDeg = 0;
  float yawDeg = 0;
  double latitudeDegOrXM = 0;   ///< latitude (deg) when detached, x offset (m) when attached
  double longitudeDegOrYM = 0;  ///< longitude (deg) when detached, y offset (m) when attached
  double altitudeMOrZM = 0;     ///< altitude (m) when detached, z offset (m) when attached
  bool operator==(const EntityControl&) const = default;
};

/// Rate Control (8): linear and angular rates of an entity (or one of its articulated parts).
struct RateControl {
  static constexpr std::uint8_t kOpcode = 8;
  static constexpr std::uint8_t kSize = 32;
  std::uint16_t entityId = 0;
  std::uint8_t articulatedPartId = 0;
  bool applyToArticulatedPart = false;
  RateFrame frame = RateFrame::World;
  float xRateMps = 0;
  float yRateMps = 0;
  float zRateMps = 0;
  float rollRateDegps = 0;
  float pitchRateDegps = 0;
  float yawRateDegps = 0;
  bool operator==(const RateControl&) const = default;
};

/// Celestial Sphere Control (9): time of day, date and the sky's bodies.
struct CelestialSphereControl {
  static constexpr std::uint8_t kOpcode = 9;
  static constexpr std::uint8_t kSize = 16;
  std::uint8_t hour = 0;               ///< 0–23
  std::uint8_t minute = 0;             ///< 0–59
  bool ephemerisModelEnabled = false;  ///< time of day runs on its own (true) or is held
  bool sunEnabled = false;
  bool moonEnabled = false;
  bool starFieldEnabled = false;
  bool dateTimeValid = false;
  std::uint32_t dateMMDDYYYY = 0;  ///< e.g. 6212024 for 21 June 2024
  float starFieldIntensityPercent = 0;
  bool operator==(const CelestialSphereControl&) const = default;
};

/// Atmosphere Control (10): global atmosphere, visibility and wind.
struct AtmosphereControl {
  static constexpr std::uint8_t kOpcode = 10;
  static constexpr std::uint8_t kSize = 32;
  bool atmosphericModelEnabled = false;
  std::uint8_t humidityPercent = 0;
  float airTemperatureC = 0;
  float visibilityRangeM = 0;
  float horizontalWindSpeedMps = 0;
  float verticalWindSpeedMps = 0;
  float windDirectionDeg = 0;       ///< direction the wind blows from, clockwise from true north
  float barometricPressureHpa = 0;  ///< millibars
  bool operator==(const AtmosphereControl&) const = default;
};

/// View Control (16): a view's (or view group's) eyepoint offset from an entity.
struct ViewControl {
  static constexpr std::uint8_t kOpcode = 16;
  static constexpr std::uint8_t kSize = 32;
  std::uint16_t viewId = 0;
  std::uint8_t groupId = 0;  ///< 0: the packet addresses the view, else the view group
  bool xOffsetEnabled = false;
  bool yOffsetEnabled = false;
  bool zOffsetEnabled = false;
  bool rollEnabled = false;
  bool pitchEnabled = false;
  bool yawEnabled = false;
  std::uint16_t entityId = 0;
  float xOffsetM = 0;
  float yOffsetM = 0;
  float zOffsetM = 0;
  float rollDeg = 0;
  float pitchDeg = 0;
  float yawDeg = 0;
  bool operator==(const ViewControl&) const = default;
};

/// View Definition (21): a view's frustum (asymmetric half-angles), mirroring and projection.
struct ViewDefinition {
  static constexpr std::uint8_t kOpcode = 21;
  static constexpr std::uint8_t kSize = 32;
  std::uint16_t viewId = 0;
  std::uint8_t groupId = 0;
  bool nearEnabled = false;
  bool farEnabled = false;
  bool leftEnabled = false;
  bool rightEnabled = false;
  bool topEnabled = false;
  bool bottomEnabled = false;
  MirrorMode mirrorMode = MirrorMode::None;
  std::uint8_t pixelReplication = 0;  ///< 0 none, 1 1×2, 2 2×1, 3 2×2, 4–7 reserved (3 bits)
  ProjectionType projectionType = ProjectionType::Perspective;
  bool reorder = false;
  std::uint8_t viewType = 0;  ///< IG-defined view type (3 bits)
  float nearM = 0;
  float farM = 0;
  float leftDeg = 0;  ///< left half-angle, negative to the left of the view axis
  float rightDeg = 0;
  float topDeg = 0;
  float bottomDeg = 0;  ///< bottom half-angle, negative below the view axis
  bool operator==(const ViewDefinition&) const = default;
};

/// HAT/HOT Request (24): height above / of terrain at a point.
struct HatHotRequest {
  static constexpr std::uint8_t kOpcode = 24;
  static constexpr std::uint8_t kSize = 32;
  std::uint16_t hatHotId = 0;
  HatHotRequestType requestType = HatHotRequestType::HeightAboveTerrain;
  CoordinateSystem coordinateSystem = CoordinateSystem::Geodetic;
  std::uint8_t updatePeriod = 0;  ///< 0: answer once; n: every n-th IG frame
  std::uint16_t entityId = 0;     ///< reference entity when coordinateSystem is Entity
  double latitudeDegOrXM = 0;
  double longitudeDegOrYM = 0;
  double altitudeMOrZM = 0;
  bool operator==(const HatHotRequest&) const = default;
};

/// Line of Sight Segment Request (25): intersection along a segment between two points.
struct LosSegmentRequest {
  static constexpr std::uint8_t kOpcode = 25;
  static constexpr std::uint8_t kSize = 64;
  std::uint16_t losId = 0;
  LosRequestType requestType = LosRequestType::Basic;
  CoordinateSystem sourceCoordinateSystem = CoordinateSystem::Geodetic;
  CoordinateSystem destinationCoordinateSystem = CoordinateSystem::Geodetic;
  CoordinateSystem responseCoordinateSystem = CoordinateSystem::Geodetic;
  bool destinationEntityIdValid = false;
  std::uint8_t alphaThreshold = 0;
  std::uint16_t entityId = 0;  ///< source entity for entity-relative points
  double sourceLatitudeDegOrXM = 0;
  double sourceLongitudeDegOrYM = 0;
  double sourceAltitudeMOrZM = 0;
  double destinationLatitudeDegOrXM = 0;
  double destinationLongitudeDegOrYM = 0;
  double destinationAltitudeMOrZM = 0;
  std::uint32_t materialMask = 0;
  std::uint8_t updatePeriod = 0;
  std::uint16_t destinationEntityId = 0;
  bool operator==(const LosSegmentRequest&) const = default;
};

/// Line of Sight Vector Request (26): intersection along a ray from a point.
struct LosVectorRequest {
  static constexpr std::uint8_t kOpcode = 26;
  static constexpr std::uint8_t kSize = 56;
  std::uint16_t losId = 0;
  LosRequestType requestType = LosRequestType::Basic;
  CoordinateSystem sourceCoordinateSystem = CoordinateSystem::Geodetic;
  CoordinateSystem responseCoordinateSystem = CoordinateSystem::Geodetic;
  std::uint8_t alphaThreshold = 0;
  std::uint16_t entityId = 0;
  float azimuthDeg = 0;    ///< clockwise from true north (or the entity's x axis)
  float elevationDeg = 0;  ///< up from the horizontal
  float minRangeM = 0;
  float maxRangeM = 0;
  double sourceLatitudeDegOrXM = 0;
  double sourceLongitudeDegOrYM = 0;
  double sourceAltitudeMOrZM = 0;
  std::uint32_t materialMask = 0;
  std::uint8_t updatePeriod = 0;
  bool operator==(const LosVectorRequest&) const = default;
};

// ---- IG → host ---------------------------------------------------------------------------

/// Start of Frame (101): leads every IG→host datagram. Carries the byte-swap magic on the wire.
struct StartOfFrame {
  static constexpr std::uint8_t kOpcode = 101;
  static constexpr std::uint8_t kSize = 24;
  std::int8_t databaseNumber = 0;  ///< the loaded database; negative while loading it (CIGI convention)
  std::uint8_t igStatus = 0;       ///< 0 normal; other values IG-defined error codes
  IgMode igMode = IgMode::Operate;
  bool timestampValid = false;
  EarthReferenceModel earthReferenceModel = EarthReferenceModel::Wgs84;
  std::uint32_t igFrameNumber = 0;
  std::uint32_t timestampTicks = 0;  ///< IG time in 10 µs ticks
  std::uint32_t lastHostFrameNumber = 0;
  bool operator==(const StartOfFrame&) const = default;
};

/// HAT/HOT Response (102).
struct HatHotResponse {
  static constexpr std::uint8_t kOpcode = 102;
  static constexpr std::uint8_t kSize = 16;
  std::uint16_t hatHotId = 0;
  bool valid = false;
  HatHotResponseType responseType = HatHotResponseType::HeightAboveTerrain;
  std::uint8_t hostFrameNumberLsn = 0;  ///< low 4 bits of the host frame the answer was computed in
  double heightM = 0;
  bool operator==(const HatHotResponse&) const = default;
};

/// HAT/HOT Extended Response (103): both heights and the surface normal.
struct HatHotExtendedResponse {
  static constexpr std::uint8_t kOpcode = 103;
  static constexpr std::uint8_t kSize = 40;
  std::uint16_t hatHotId = 0;
  bool valid = false;
  std::uint8_t hostFrameNumberLsn = 0;
  double heightAboveTerrainM = 0;
  double heightOfTerrainM = 0;
  std::uint32_t materialCode = 0;
  float normalAzimuthDeg = 0;
  float normalElevationDeg = 0;
  bool operator==(const HatHotExtendedResponse&) const = default;
};

/// Line of Sight Response (104).
struct LosResponse {
  static constexpr std::uint8_t kOpcode = 104;
  static constexpr std::uint8_t kSize = 16;
  std::uint16_t losId = 0;
  bool valid = false;
  bool entityIdValid = false;
  bool visible = false;
  std::uint8_t hostFrameNumberLsn = 0;
  std::uint8_t responseCount = 0;
  std::uint16_t entityId = 0;
  double rangeM = 0;
  bool operator==(const LosResponse&) const = default;
};

/// Line of Sight Extended Response (105): range, intersection point, surface colour and normal.
struct LosExtendedResponse {
  static constexpr std::uint8_t kOpcode = 105;
  static constexpr std::uint8_t kSize = 56;
  std::uint16_t losId = 0;
  bool valid = false;
  bool entityIdValid = false;
  bool rangeValid = false;
  bool visible = false;
  std::uint8_t hostFrameNumberLsn = 0;
  std::uint8_t responseCount = 0;
  std::uint16_t entityId = 0;
  double rangeM = 0;
  double latitudeDegOrXM = 0;
  double longitudeDegOrYM = 0;
  double altitudeMOrZM = 0;
  std::uint8_t red = 0;
  std::uint8_t green = 0;
  std::uint8_t blue = 0;
  std::uint8_t alpha = 0;
  std::uint32_t materialCode = 0;
  float normalAzimuthDeg = 0;
  float normalElevationDeg = 0;
  bool operator==(const LosExtendedResponse&) const = default;
};

/// Every packet a host→IG datagram may carry that the codec decodes (IG Control first).
using HostPacket = std::variant<IgControl, EntityControl, RateControl, CelestialSphereControl, AtmosphereControl,
                                ViewControl, ViewDefinition, HatHotRequest, LosSegmentRequest, LosVectorRequest>;

/// Every packet an IG→host datagram may carry that the codec decodes (Start of Frame first).
using IgPacket = std::variant<StartOfFrame, HatHotResponse, HatHotExtendedResponse, LosResponse, LosExtendedResponse>;

}  // namespace fieldcast::io::cigi

// Writes the capture the tshark interop test judges (cigi_tshark_check.sh): four CIGI 3.3
// datagrams over UDP on 127.0.0.1 — host→IG and IG→host, each in big- and little-endian byte
// order — carrying every packet the codec encodes, plus the values tshark must print for them.
//
// Usage: fieldcast_cigi_capture <output directory>
//   writes <dir>/cigi.pcap and <dir>/expected.tsv (frame number, tshark field name, value; one
//   line per field, booleans and enumerations as integers).
#include <io_bridge/PcapWriter.h>
#include <io_bridge/cigi/MessageBuilder.h>

#include "SamplePackets.h"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

using namespace fieldcast::io::cigi;
namespace td = fieldcast::io::cigi::testdata;

constexpr std::uint16_t kIgPort = 8004;    // the IG listens here
constexpr std::uint16_t kHostPort = 8005;  // the host listens here

/// Expected tshark values of one frame.
class Expectations {
 public:
  explicit Expectations(std::ofstream& out) : mOut(out) {}
  void frame(int number) { mFrame = number; }
  template <class T>
  void field(const char* name, T value) {
    std::ostringstream text;
    if constexpr (std::is_enum_v<T>) {
      text << static_cast<int>(value);
    } else if constexpr (std::is_same_v<T, bool> || sizeof(T) == 1) {
      text << static_cast<int>(value);
    } else {
      text.precision(17);
      text << value;
    }
    mOut << mFrame << '\t' << name << '\t' << text.str() << '\n';
  }

 private:
  std::ofstream& mOut;
  int mFrame = 0;
};

void expectHostPackets(Expectations& e) {
  const IgControl ig = td::sampleIgControl();
  e.field("cigi.version", kMajorVersion);
  e.field("cigi.ig_control.minor_version", kMinorVersion);
  e.field("cigi.ig_control.db_number", ig.databaseNumber);
  e.field("cigi.ig_control.ig_mode", ig.igMode);
  e.field("cigi.ig_control.timestamp_valid", ig.timestampValid);
  e.field("cigi.ig_control.extrapolation_enable", ig.extrapolationEnabled);
  e.field("cigi.ig_control.host_frame_number", ig.hostFrameNumber);
  e.field("cigi.ig_control.timestamp", ig.timestampTicks);
  e.field("cigi.ig_control.last_ig_frame_number", ig.lastIgFrameNumber);

  const EntityControl ec = td::sampleEntityControl();
  e.field("cigi.entity_control.entity_id", ec.entityId);
  e.field("cigi.entity_control.entity_state", ec.entityState);
  e.field("cigi.entity_control.attach_state", ec.attachState);
  e.field("cigi.entity_control.coll_det_request", ec.collisionDetectionEnabled);
  e.field("cigi.entity_control.inherit_alpha", ec.inheritAlpha);
  e.field("cigi.entity_control.ground_ocean_clamp", ec.groundOceanClamp);
  e.field("cigi.entity_control.animation_dir", ec.animationDirection);
  e.field("cigi.entity_control.animation_loop_mode", ec.animationLoopMode);
  e.field("cigi.entity_control.animation_state", ec.animationState);
  e.field("cigi.entity_control.extrapolation_enable", ec.extrapolationEnabled);
  e.field("cigi.entity_control.alpha", ec.alpha);
  e.field("cigi.entity_control.entity_type", ec.entityType);
  e.field("cigi.entity_control.parent_id", ec.parentId);
  e.field("cigi.entity_control.roll", ec.rollDeg);
  e.field("cigi.entity_control.pitch", ec.pitchDeg);
  e.field("cigi.entity_control.yaw", ec.yawDeg);
  e.field("cigi.entity_control.lat_xoff", ec.latitudeDegOrXM);
  e.field("cigi.entity_control.lon_yoff", ec.longitudeDegOrYM);
  e.field("cigi.entity_control.alt_zoff", ec.altitudeMOrZM);

  const RateControl rc = td::sampleRateControl();
  e.field("cigi.rate_control.entity_id", rc.entityId);
  e.field("cigi.rate_control.part_id", rc.articulatedPartId);
  e.field("cigi.rate_control.apply_to_part", rc.applyToArticulatedPart);
  e.field("cigi.rate_control.coordinate_system", rc.frame);
  e.field("cigi.rate_control.x_rate", rc.xRateMps);
  e.field("cigi.rate_control.y_rate", rc.yRateMps);
  e.field("cigi.rate_control.z_rate", rc.zRateMps);
  e.field("cigi.rate_control.roll_rate", rc.rollRateDegps);
  e.field("cigi.rate_control.pitch_rate", rc.pitchRateDegps);
  e.field("cigi.rate_control.yaw_rate", rc.yawRateDegps);

  const CelestialSphereControl cs = td::sampleCelestialSphereControl();
  e.field("cigi.celestial_sphere_control.hour", cs.hour);
  e.field("cigi.celestial_sphere_control.minute", cs.minute);
  e.field("cigi.celestial_sphere_control.ephemeris_enable", cs.ephemerisModelEnabled);
  e.field("cigi.celestial_sphere_control.sun_enable", cs.sunEnabled);
  e.field("cigi.celestial_sphere_control.moon_enable", cs.moonEnabled);
  e.field("cigi.celestial_sphere_control.star_enable", cs.starFieldEnabled);
  e.field("cigi.celestial_sphere_control.date_time_valid", cs.dateTimeValid);
  e.field("cigi.celestial_sphere_control.date", cs.dateMMDDYYYY);
  e.field("cigi.celestial_sphere_control.star_intensity", cs.starFieldIntensityPercent);

  const AtmosphereControl ac = td::sampleAtmosphereControl();
  e.field("cigi.atmosphere_control.atmospheric_model_enable", ac.atmosphericModelEnabled);
  e.field("cigi.atmosphere_control.humidity", ac.humidityPercent);
  e.field("cigi.atmosphere_control.air_temp", ac.airTemperatureC);
  e.field("cigi.atmosphere_control.visibility_range", ac.visibilityRangeM);
  e.field("cigi.atmosphere_control.horiz_wind", ac.horizontalWindSpeedMps);
  e.field("cigi.atmosphere_control.vert_wind", ac.verticalWindSpeedMps);
  e.field("cigi.atmosphere_control.wind_direction", ac.windDirectionDeg);
  e.field("cigi.atmosphere_control.barometric_pressure", ac.barometricPressureHpa);

  const ViewControl vc = td::sampleViewControl();
  e.field("cigi.view_control.view_id", vc.viewId);
  e.field("cigi.view_control.group_id", vc.groupId);
  e.field("cigi.view_control.xoff_enable", vc.xOffsetEnabled);
  e.field("cigi.view_control.yoff_enable", vc.yOffsetEnabled);
  e.field("cigi.view_control.zoff_enable", vc.zOffsetEnabled);
  e.field("cigi.view_control.roll_enable", vc.rollEnabled);
  e.field("cigi.view_control.pitch_enable", vc.pitchEnabled);
  e.field("cigi.view_control.yaw_enable", vc.yawEnabled);
  e.field("cigi.view_control.entity_id", vc.entityId);
  e.field("cigi.view_control.xoff", vc.xOffsetM);
  e.field("cigi.view_control.yoff", vc.yOffsetM);
  e.field("cigi.view_control.zoff", vc.zOffsetM);
  e.field("cigi.view_control.roll", vc.rollDeg);
  e.field("cigi.view_control.pitch", vc.pitchDeg);
  e.field("cigi.view_control.yaw", vc.yawDeg);

  const ViewDefinition vd = td::sampleViewDefinition();
  e.field("cigi.view_def.view_id", vd.viewId);
  e.field("cigi.view_def.group_id", vd.groupId);
  e.field("cigi.view_def.near_enable", vd.nearEnabled);
  e.field("cigi.view_def.far_enable", vd.farEnabled);
  e.field("cigi.view_def.left_enable", vd.leftEnabled);
  e.field("cigi.view_def.right_enable", vd.rightEnabled);
  e.field("cigi.view_def.top_enable", vd.topEnabled);
  e.field("cigi.view_def.bottom_enable", vd.bottomEnabled);
  e.field("cigi.view_def.mirror_mode", vd.mirrorMode);
  e.field("cigi.view_def.pixel_replication", vd.pixelReplication);
  e.field("cigi.view_def.projection_type", vd.projectionType);
  e.field("cigi.view_def.reorder", vd.reorder);
  e.field("cigi.view_def.view_type", vd.viewType);
  e.field("cigi.view_def.near", vd.nearM);
  e.field("cigi.view_def.far", vd.farM);
  e.field("cigi.view_def.left", vd.leftDeg);
  e.field("cigi.view_def.right", vd.rightDeg);
  e.field("cigi.view_def.top", vd.topDeg);
  e.field("cigi.view_def.bottom", vd.bottomDeg);

  const HatHotRequest hr = td::sampleHatHotRequest();
  e.field("cigi.hat_hot_request.hat_hot_id", hr.hatHotId);
  e.field("cigi.hat_hot_request.type", hr.requestType);
  e.field("cigi.hat_hot_request.coordinate_system", hr.coordinateSystem);
  e.field("cigi.hat_hot_request.update_period", hr.updatePeriod);
  e.field("cigi.hat_hot_request.entity_id", hr.entityId);
  e.field("cigi.hat_hot_request.lat_xoff", hr.latitudeDegOrXM);
  e.field("cigi.hat_hot_request.lon_yoff", hr.longitudeDegOrYM);
  e.field("cigi.hat_hot_request.alt_zoff", hr.altitudeMOrZM);

  const LosSegmentRequest ls = td::sampleLosSegmentRequest();
  e.field("cigi.los_segment_request.los_id", ls.losId);
  e.field("cigi.los_segment_request.type", ls.requestType);
  e.field("cigi.los_segment_request.source_coord", ls.sourceCoordinateSystem);
  e.field("cigi.los_segment_request.destination_coord", ls.destinationCoordinateSystem);
  e.field("cigi.los_segment_request.response_coord", ls.responseCoordinateSystem);
  e.field("cigi.los_segment_request.destination_entity_id_valid", ls.destinationEntityIdValid);
  e.field("cigi.los_segment_request.alpha_threshold", ls.alphaThreshold);
  e.field("cigi.los_segment_request.entity_id", ls.entityId);
  e.field("cigi.los_segment_request.source_lat_xoff", ls.sourceLatitudeDegOrXM);
  e.field("cigi.los_segment_request.source_lon_yoff", ls.sourceLongitudeDegOrYM);
  e.field("cigi.los_segment_request.source_alt_zoff", ls.sourceAltitudeMOrZM);
  e.field("cigi.los_segment_request.destination_lat_xoff", ls.destinationLatitudeDegOrXM);
  e.field("cigi.los_segment_request.destination_lon_yoff", ls.destinationLongitudeDegOrYM);
  e.field("cigi.los_segment_request.destination_alt_zoff", ls.destinationAltitudeMOrZM);
  e.field("cigi.los_segment_request.material_mask", ls.materialMask);
  e.field("cigi.los_segment_request.update_period", ls.updatePeriod);
  e.field("cigi.los_segment_request.destination_entity_id", ls.destinationEntityId);

  const LosVectorRequest lv = td::sampleLosVectorRequest();
  e.field("cigi.los_vector_request.los_id", lv.losId);
  e.field("cigi.los_vector_request.type", lv.requestType);
  e.field("cigi.los_vector_request.source_coord", lv.sourceCoordinateSystem);
  e.field("cigi.los_vector_request.response_coord", lv.responseCoordinateSystem);
  e.field("cigi.los_vector_request.alpha", lv.alphaThreshold);
  e.field("cigi.los_vector_request.entity_id", lv.entityId);
  e.field("cigi.los_vector_request.azimuth", lv.azimuthDeg);
  e.field("cigi.los_vector_request.elevation", lv.elevationDeg);
  e.field("cigi.los_vector_request.min_range", lv.minRangeM);
  e.field("cigi.los_vector_request.max_range", lv.maxRangeM);
  e.field("cigi.los_vector_request.source_lat_xoff", lv.sourceLatitudeDegOrXM);
  e.field("cigi.los_vector_request.source_lon_yoff", lv.sourceLongitudeDegOrYM);
  e.field("cigi.los_vector_request.source_alt_zoff", lv.sourceAltitudeMOrZM);
  e.field("cigi.los_vector_request.material_mask", lv.materialMask);
  e.field("cigi.los_vector_request.update_period", lv.updatePeriod);
}

void expectIgPackets(Expectations& e) {
  const StartOfFrame sof = td::sampleStartOfFrame();
  e.field("cigi.version", kMajorVersion);
  e.field("cigi.sof.minor_version", kMinorVersion);
  e.field("cigi.sof.db_number", sof.databaseNumber);
  e.field("cigi.sof.ig_status", sof.igStatus);
  e.field("cigi.sof.ig_mode", sof.igMode);
  e.field("cigi.sof.timestamp_valid", sof.timestampValid);
  e.field("cigi.sof.earth_reference_model", sof.earthReferenceModel);
  e.field("cigi.sof.ig_frame_number", sof.igFrameNumber);
  e.field("cigi.sof.timestamp", sof.timestampTicks);
  e.field("cigi.sof.last_host_frame_number", sof.lastHostFrameNumber);

  const HatHotResponse hr = td::sampleHatHotResponse();
  e.field("cigi.hat_hot_response.hat_hot_id", hr.hatHotId);
  e.field("cigi.hat_hot_response.valid", hr.valid);
  e.field("cigi.hat_hot_response.type", hr.responseType);
  e.field("cigi.hat_hot_response.host_frame_number_lsn", hr.hostFrameNumberLsn);
  e.field("cigi.hat_hot_response.height", hr.heightM);

  const HatHotExtendedResponse hx = td::sampleHatHotExtendedResponse();
  e.field("cigi.hat_hot_ext_response.hat_hot_id", hx.hatHotId);
  e.field("cigi.hat_hot_ext_response.valid", hx.valid);
  e.field("cigi.hat_hot_ext_response.host_frame_number_lsn", hx.hostFrameNumberLsn);
  e.field("cigi.hat_hot_ext_response.hat", hx.heightAboveTerrainM);
  e.field("cigi.hat_hot_ext_response.hot", hx.heightOfTerrainM);
  e.field("cigi.hat_hot_ext_response.material_code", hx.materialCode);
  e.field("cigi.hat_hot_ext_response.normal_vector_azimuth", hx.normalAzimuthDeg);
  e.field("cigi.hat_hot_ext_response.normal_vector_elevation", hx.normalElevationDeg);

  const LosResponse lr = td::sampleLosResponse();
  e.field("cigi.los_response.los_id", lr.losId);
  e.field("cigi.los_response.valid", lr.valid);
  e.field("cigi.los_response.entity_id_valid", lr.entityIdValid);
  e.field("cigi.los_response.visible", lr.visible);
  e.field("cigi.los_response.host_frame_number_lsn", lr.hostFrameNumberLsn);
  e.field("cigi.los_response.count", lr.responseCount);
  e.field("cigi.los_response.entity_id", lr.entityId);
  e.field("cigi.los_response.range", lr.rangeM);

  const LosExtendedResponse lx = td::sampleLosExtendedResponse();
  e.field("cigi.3_2_los_ext_response.los_id", lx.losId);
  e.field("cigi.3_2_los_ext_response.valid", lx.valid);
  e.field("cigi.3_2_los_ext_response.entity_id_valid", lx.entityIdValid);
  e.field("cigi.3_2_los_ext_response.range_valid", lx.rangeValid);
  e.field("cigi.3_2_los_ext_response.visible", lx.visible);
  e.field("cigi.3_2_los_ext_response.host_frame_number_lsn", lx.hostFrameNumberLsn);
  e.field("cigi.3_2_los_ext_response.response_count", lx.responseCount);
  e.field("cigi.3_2_los_ext_response.entity_id", lx.entityId);
  e.field("cigi.3_2_los_ext_response.range", lx.rangeM);
  e.field("cigi.3_2_los_ext_response.lat_xoff", lx.latitudeDegOrXM);
  e.field("cigi.3_2_los_ext_response.lon_yoff", lx.longitudeDegOrYM);
  e.field("cigi.3_2_los_ext_response.alt_zoff", lx.altitudeMOrZM);
  e.field("cigi.3_2_los_ext_response.red", lx.red);
  e.field("cigi.3_2_los_ext_response.green", lx.green);
  e.field("cigi.3_2_los_ext_response.blue", lx.blue);
  e.field("cigi.3_2_los_ext_response.alpha", lx.alpha);
  e.field("cigi.3_2_los_ext_response.material_code", lx.materialCode);
  e.field("cigi.3_2_los_ext_response.normal_vector_azimuth", lx.normalAzimuthDeg);
  e.field("cigi.3_2_los_ext_response.normal_vector_elevation", lx.normalElevationDeg);
}

std::span<const std::uint8_t> hostMessage(HostMessageBuilder& b) {
  b.start(td::sampleIgControl());
  b.add(td::sampleEntityControl());
  b.add(td::sampleRateControl());
  b.add(td::sampleCelestialSphereControl());
  b.add(td::sampleAtmosphereControl());
  b.add(td::sampleViewControl());
  b.add(td::sampleViewDefinition());
  b.add(td::sampleHatHotRequest());
  b.add(td::sampleLosSegmentRequest());
  b.add(td::sampleLosVectorRequest());
  return b.bytes();
}

std::span<const std::uint8_t> igMessage(IgMessageBuilder& b) {
  b.start(td::sampleStartOfFrame());
  b.add(td::sampleHatHotResponse());
  b.add(td::sampleHatHotExtendedResponse());
  b.add(td::sampleLosResponse());
  b.add(td::sampleLosExtendedResponse());
  return b.bytes();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <output directory>\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path dir = argv[1];
    std::filesystem::create_directories(dir);
    fieldcast::io::PcapWriter pcap((dir / "cigi.pcap").string());
    std::ofstream expectedFile(dir / "expected.tsv");
    if (!expectedFile) throw std::runtime_error((dir / "expected.tsv").string() + ": cannot create");
    Expectations expected(expectedFile);

    std::uint64_t timeUs = 1'700'000'000'000'000;
    for (const ByteOrder order : {ByteOrder::Big, ByteOrder::Little}) {
      HostMessageBuilder host(order);
      pcap.writeUdp({.port = kHostPort}, {.port = kIgPort}, hostMessage(host), timeUs += 16'667);
      expected.frame(pcap.frames());
      expectHostPackets(expected);

      IgMessageBuilder ig(order);
      pcap.writeUdp({.port = kIgPort}, {.port = kHostPort}, igMessage(ig), timeUs += 1'000);
      expected.frame(pcap.frames());
      expectIgPackets(expected);
    }
    std::printf("%s: %d frames\n", (dir / "cigi.pcap").c_str(), pcap.frames());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast_cigi_capture: %s\n", e.what());
    return 1;
  }
}

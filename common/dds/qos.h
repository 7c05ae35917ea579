// QoS per stream kind: the one place where mostar's DDS QoS is defined.
//
// - kVideo: reliable, keep last 1, volatile. Heartbeat every `repair_period` (50 ms by
//   default), none piggybacked on writes; the publisher skips a pair while the previous one is
//   unacknowledged (ack-clock), so video never offers more than the link carries. Best-effort
//   readers (ROS tools) match too.
// - kSensor: best effort, keep last kSensorDepth, volatile: scans, odometry (ROS
//   SensorDataQoS-compatible: depth is not part of matching).
// - kCommand: reliable, keep last 1 (readers 8), volatile, shared ownership, deadline 200 ms,
//   manual-by-topic liveliness 500 ms. Ownership is shared: the robot hears every pilot and
//   keeps the lease holder's commands (SafetyGovernor), so no writer strength a client picks
//   decides who drives.
// - kState: reliable, keep last 1, transient local: lease, health, camera info (late joiners
//   get the latest).
// - kControl: reliable, keep last 10, volatile: control requests, e-stop, clock probes.
// Readers hold at most their history depth of one instance (topics are keyless; max_instances
// 1, max_samples depth + kMissingSampleAllowance); kCommand and kControl readers preallocate
// samples of the type's maximum size (their types are bounded, idl/mostar_msgs.idl), so a
// bigger sample is refused before it is read.
// All writers publish asynchronously (Fast DDS's own sending thread), so write() never blocks
// the caller on a full transport.
#pragma once

#include <chrono>
#include <cstdint>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <string>

namespace mostar::dds {

enum class Stream { kVideo, kSensor, kCommand, kState, kControl };

const char* StreamName(Stream stream);

eprosima::fastdds::dds::DataWriterQos WriterQos(Stream stream);

// Default heartbeat period of the video writers.
constexpr std::chrono::milliseconds kDefaultVideoRepairPeriod{50};
// kVideo writer QoS for the robot's ack-clock lanes (RobotNode: keep-last-1 writers that each
// carry at most one unacknowledged pair), heartbeat period `repair_period` (> 0): how often
// readers are asked what they miss, and so how often a lost fragment is sent again. Fast DDS
// 2.9 answers every NACK_FRAG at once (no NACK suppression for fragments), so a period shorter
// than the round trip sends each lost fragment several times: on long links set it to about the
// round trip. Unlike WriterQos(kVideo), a heartbeat also follows every write: each reader
// acknowledges the pair, or asks for its missing fragments, one round trip after it was sent
// instead of up to a repair period later, which frees the lane that much sooner. (A lane never
// holds an older unacknowledged pair, so this does not repeat requests for earlier pairs.)
eprosima::fastdds::dds::DataWriterQos VideoWriterQos(std::chrono::milliseconds repair_period);
eprosima::fastdds::dds::DataReaderQos ReaderQos(Stream stream);

// The H.264 stream (rt/mostar/camera/stereo/h264): every access unit matters (a lost one breaks
// the pictures until the next IDR), so reliable, keep last `depth` (> 0) access units, which
// bounds memory and never blocks the writer: a reader that falls that far behind loses the
// oldest, sees the gap in the AU numbers and asks for an IDR. Heartbeat every `repair_period`
// and never after a write or a repair: a reader asks for what it misses once per period (see
// VideoWriterQos on the round trip), not once per message (video_stream_qos_test.cc).
// `repair_deadline` > 0 (a NACK deadline, as WebRTC's): an AU leaves the writer's history that
// long after it was written (DDS lifespan, on the writer's own clock) and is no longer repaired;
// a reader still missing part of it gets a GAP instead, delivers the AUs behind it at once and
// sees the jump in the AU numbers (it asks for an IDR). Without one, a lost fragment holds every
// later AU at the reader until it is repaired or `depth` newer AUs pushed it out. 0: no
// deadline.
eprosima::fastdds::dds::DataWriterQos VideoStreamWriterQos(
    std::chrono::milliseconds repair_period, int32_t depth,
    std::chrono::milliseconds repair_deadline = std::chrono::milliseconds::zero());
eprosima::fastdds::dds::DataReaderQos VideoStreamReaderQos(int32_t depth);
inline constexpr int32_t kVideoStreamDepth = 30;  // 1 s at 30 Hz
// Changes an enabled stream writer's repair deadline (its lifespan; 0: none) while it runs.
// Fast DDS 2.9 announces the writer's new QoS to every matched participant, so call it rarely,
// and from the thread that writes (its set_qos does not lock against write). False with `error`.
bool SetRepairDeadline(eprosima::fastdds::dds::DataWriter* writer,
                       std::chrono::milliseconds repair_deadline, std::string* error);

// `qos` with the endpoint in the one DDS partition `partition` (Fast DDS 2.9's "partitions"
// endpoint property; the publisher's or subscriber's own partitions no longer apply). Commands,
// e-stops, control requests and clock pings travel in their writer's client partition
// (common/identity/sender_partition.h).
eprosima::fastdds::dds::DataWriterQos InPartition(eprosima::fastdds::dds::DataWriterQos qos,
                                                  const std::string& partition);
eprosima::fastdds::dds::DataReaderQos InPartition(eprosima::fastdds::dds::DataReaderQos qos,
                                                  const std::string& partition);

// Deadline of the command stream: a pilot that sends nothing for this long is considered gone.
constexpr double kCommandDeadlineSeconds = 0.2;
// Liveliness lease of the command stream (MANUAL_BY_TOPIC: each write asserts it).
constexpr double kCommandLivelinessSeconds = 0.5;
// History depth of command readers: several pilots write the one (keyless) instance.
constexpr int32_t kCommandReaderDepth = 8;
// Sensor history: 0.43 s of LMS200 scans at 75 Hz (500 kBd), 0.64 s of odometry at 50 Hz. A
// sending or receiving thread stalled for less than that loses no sample (depth 5 was 0.53 s
// of scans at 9.4 Hz but only 67 ms at 75 Hz).
constexpr int32_t kSensorDepth = 32;
// Reader sample limit beyond the depth: room for samples a reliable reader knows are missing.
constexpr int32_t kMissingSampleAllowance = 32;

}  // namespace mostar::dds

// Plain types (common/types, recording_format.h) <-> recording protobuf messages
// (common/record/recording.proto), field by field.
#pragma once

#include <string>

#include "common/record/recording.pb.h"
#include "common/record/recording_format.h"

namespace mostar::record {

void ToProto(const RecordingInfo& info, proto::Header* header);
// Leaves `format_version` to the caller (it comes from the prelude).
void FromProto(const proto::Header& header, RecordingInfo* info);

// Sets log_time and the payload; offset/size_bytes are not stored.
void ToProto(const RecordedMessage& message, proto::Record* record);

enum class FromProtoResult { kOk, kIndex, kUnknown };
// kIndex: an index record (not a data record); kUnknown: no payload this reader knows (written
// by a newer writer); `message` is then unchanged. Unknown enum values of health states become
// DeviceState::kError / WatchdogState::kIdle.
FromProtoResult FromProto(const proto::Record& record, RecordedMessage* message);

}  // namespace mostar::record

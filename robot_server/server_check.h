// robot_server --check-config: the configuration, the files and devices it names, the role
// table against the PKI's names, and the DDS profile, each problem with its fix, without
// opening a device or starting DDS (docs/packages.md). Safe beside a running server.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "common/config/config_report.h"
#include "common/dds/participant.h"
#include "robot_server/server_config.pb.h"

namespace mostar::server {

// Every certificate make_pki.sh issued, name -> role ("robot", "pilot", "observer", "relay"):
// the `roles` file it puts into the robot's bundle. False with `error` when unreadable.
bool ReadPkiRoles(const std::string& path, std::map<std::string, std::string>* roles,
                  std::string* error);

// The configuration (already loaded, flags applied): drive settings and role table, the state
// folder, the source's files (scene, intrinsics, recordings; relative to `config_dir`, then
// the installed examples) and devices (laser, motor board, cameras, sonar bus, GPIO chip).
void CheckServerFiles(const ServerConfig& config, const std::string& config_dir,
                      ConfigReport* report);

// The role table: a placeholder name left in, nobody allowed to drive; with `pki_roles`, every
// name has a certificate, every pilot certificate is a PILOT and every relay an OBSERVER.
void CheckRoleTable(const ServerConfig& config,
                    const std::optional<std::map<std::string, std::string>>& pki_roles,
                    ConfigReport* report);

// Everything: CheckServerFiles, the DDS profile of `dds` (dds::CheckDdsProfile, service user
// mostar), then CheckRoleTable with the `roles` file beside the robot's certificate.
void CheckServerConfig(const ServerConfig& config, const std::string& config_dir,
                       const dds::ParticipantOptions& dds, ConfigReport* report);

}  // namespace mostar::server

#include "robot_server/server_check.h"

#include <glob.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "common/config/config_paths.h"
#include "common/dds/profile_check.h"
#include "robot_server/camera/camera_factory.h"
#include "robot_server/camera/camera_intrinsics.h"
#include "robot_server/drive/drive_config.h"
#include "robot_server/laser/lms200_session.h"
#include "robot_server/server_options.h"
#include "robot_server/sim/scene.h"
#include "robot_server/sim/sim_world.h"

namespace mostar::server {
namespace {

bool Exists(const std::string& path) { return access(path.c_str(), F_OK) == 0; }

// A device node the server opens: present, or a problem naming `what` and the udev rule.
void CheckDevice(const std::string& what, const std::string& path, const std::string& fix,
                 ConfigReport* report) {
  if (Exists(path)) {
    report->Ok(what + " " + path + " present");
  } else {
    report->Fail(what + " " + path + " does not exist", fix);
  }
}

std::string UdevFix(const std::string& rule, const std::string& key) {
  return "connect it; for a USB serial adapter set its serial number in " + rule +
         " (copy /lib/udev/rules.d/" + rule +
         " to /etc/udev/rules.d/ and edit it; "
         "`udevadm info -a /dev/ttyUSB0` shows it), then `udevadm trigger`; or set " +
         key + " to the device's path";
}

// A data file named by the configuration: found (relative to the file, then the installed
// examples) and loadable by `load`.
template <typename Load>
void CheckDataFile(const std::string& key, const std::string& file, const std::string& config_dir,
                   Load load, ConfigReport* report) {
  const std::string path = ResolveConfigPath(file, config_dir);
  std::string error;
  if (!Exists(path)) {
    report->Fail(key + ": " + path + " does not exist",
                 "relative names are taken from the configuration file's folder, then from " +
                     InstalledConfigDir() + "; give an absolute path or copy the file there");
  } else if (!load(path, &error)) {
    report->Fail(key + ": " + error, "correct the file, or point " + key + " at another one");
  } else {
    report->Ok(key + " " + path + " loads");
  }
}

void CheckSimSource(const ServerConfig& config, const std::string& config_dir,
                    ConfigReport* report) {
  CheckDataFile(
      "scene_file", config.scene_file(), config_dir,
      [](const std::string& path, std::string* error) {
        sim::proto::Scene scene;
        return sim::LoadScene(path, &scene, error);
      },
      report);
  std::string error;
  if (sim::ValidateSimConfig(config.sim(), "sim", &error)) {
    report->Ok("sim section valid");
  } else {
    report->Fail(error, "correct the sim section (robot_server/sim/sim_config.proto)");
  }
}

void CheckCamera(const ServerConfig& config, const std::string& config_dir, ConfigReport* report) {
  const camera::CameraConfig& c = config.camera();
  std::string error;
  if (!camera::ValidateCameraConfig(c, &error)) {
    report->Fail("camera: " + error, "correct the camera section (docs/cameras.md)");
    return;
  }
  switch (c.backend()) {
    case camera::CameraConfig::V4L2:
      CheckDevice("left camera", c.v4l2().left_device(),
                  UdevFix("65-mostar-cameras.rules", "camera.v4l2.left_device"), report);
      CheckDevice("right camera", c.v4l2().right_device(),
                  UdevFix("65-mostar-cameras.rules", "camera.v4l2.right_device"), report);
      break;
    case camera::CameraConfig::DC1394: {
      glob_t g{};
      const bool any = glob("/dev/fw*", 0, nullptr, &g) == 0 && g.gl_pathc > 0;
      globfree(&g);
      if (any) {
        report->Ok("IEEE1394 devices present (/dev/fw*)");
      } else {
        report->Fail("no IEEE1394 device (/dev/fw*): the cameras are not seen",
                     "connect the cameras and their FireWire card (the firewire-ohci module)");
      }
      break;
    }
    default:
      report->Ok("camera backend needs no device");
  }
  if (!c.left_intrinsics_file().empty() || !c.right_intrinsics_file().empty()) {
    for (const std::string& file : {c.left_intrinsics_file(), c.right_intrinsics_file()}) {
      CheckDataFile(
          "camera intrinsics", file, config_dir,
          [](const std::string& path, std::string* why) {
            camera::CameraIntrinsics k;
            return camera::LoadCameraIntrinsics(path, &k, why);
          },
          report);
    }
  }
}

void CheckHardwareSource(const ServerConfig& config, const std::string& config_dir,
                         ConfigReport* report) {
  std::string error;
  if (!laser::ValidateLms200Config(config.laser(), &error)) {
    report->Fail("laser: " + error, "correct the laser section (docs/lms200.md)");
  } else if (config.laser().replay().file().empty()) {
    CheckDevice("LMS200 port", config.laser().port(),
                UdevFix("60-mostar-lms200.rules", "laser.port"), report);
  }
  if (config.camera().backend() != camera::CameraConfig::REPLAY) {
    CheckCamera(config, config_dir, report);
  }
  drive::DriveSettings settings;
  if (drive::DriveSettingsFromProto(config.drive(), &settings, &error)) {
    CheckDevice("motor board port", settings.motors.port,
                UdevFix("70-mostar-drive.rules", "drive.motor_board.port"), report);
  }
  if (config.sonar().sensors_size() > 0) {
    CheckDevice("sonar I2C bus", config.sonar().bus(),
                "load the i2c-dev module (echo i2c-dev > /etc/modules-load.d/i2c-dev.conf) or "
                "set sonar.bus",
                report);
  }
  if (config.bumpers().backend() == BumperConfig::GPIOD) {
    const std::string chip = config.bumpers().chip();
    CheckDevice("bumper GPIO chip", chip.rfind('/', 0) == 0 ? chip : "/dev/" + chip,
                "set bumpers.chip to the chip of the bumper lines (`gpiodetect` lists them)",
                report);
  }
}

void CheckReplayFiles(const ServerConfig& config, const std::string& config_dir,
                      ConfigReport* report) {
  auto exists = [](const std::string& path, std::string* error) {
    if (Exists(path)) return true;
    *error = path + " does not exist";
    return false;
  };
  if (config.camera().backend() == camera::CameraConfig::REPLAY) {
    CheckDataFile("camera.replay.file", config.camera().replay().file(), config_dir, exists,
                  report);
  }
  if (!config.laser().replay().file().empty()) {
    CheckDataFile("laser.replay.file", config.laser().replay().file(), config_dir, exists, report);
  }
}

}  // namespace

bool ReadPkiRoles(const std::string& path, std::map<std::string, std::string>* roles,
                  std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot open " + path;
    return false;
  }
  roles->clear();
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream fields(line);
    std::string name, role;
    if (!(fields >> name)) continue;  // blank line
    if (!(fields >> role)) {
      *error = path + ":" + std::to_string(number) + ": expected 'NAME ROLE'";
      return false;
    }
    (*roles)[name] = role;
  }
  return true;
}

void CheckServerFiles(const ServerConfig& config, const std::string& config_dir,
                      ConfigReport* report) {
  drive::DriveSettings settings;
  std::string error;
  if (drive::DriveSettingsFromProto(config.drive(), &settings, &error)) {
    report->Ok("drive section valid");
  } else {
    report->Fail("drive: " + error, "correct the drive section (docs/safety.md)");
  }
  // A repair deadline no repair can meet gives up every lost fragment (docs/cameras.md).
  const int deadline_ms = config.dds().video_repair_deadline_ms();
  const int repair_ms = config.dds().video_repair_period_ms();
  if (deadline_ms > 0 && deadline_ms <= repair_ms) {
    report->Fail("dds.video_repair_deadline_ms " + std::to_string(deadline_ms) +
                     " is not longer than dds.video_repair_period_ms " + std::to_string(repair_ms) +
                     ": no lost fragment can be repaired in time",
                 "give a repair room: more than the repair period plus the round trip (250 ms "
                 "with the default 50 ms period on a LAN-like path; 650 ms with the Internet "
                 "recipe's 250 ms), or 0 to repair without a deadline");
  }
  std::string state_dir;
  if (!EstopStateDirectory(config, config_dir, &state_dir, &error)) {
    report->Fail(error, "set state_dir (the packaged unit keeps /var/lib/mostar)");
  } else if (!state_dir.empty()) {
    struct stat st {};
    if (stat(state_dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
      report->Ok("e-stop latch folder " + state_dir + " present");
    } else {
      report->Fail("e-stop latch folder " + state_dir + " does not exist",
                   "systemd-tmpfiles --create mostar.conf (the package's folders), or create "
                   "it owned by the user the server runs as");
    }
  }
  switch (config.source()) {
    case ServerConfig::SIM:
      CheckSimSource(config, config_dir, report);
      break;
    case ServerConfig::HARDWARE:
      CheckHardwareSource(config, config_dir, report);
      break;
    default:
      report->Ok("test pattern source needs no device");
  }
  CheckReplayFiles(config, config_dir, report);
}

void CheckRoleTable(const ServerConfig& config,
                    const std::optional<std::map<std::string, std::string>>& pki_roles,
                    ConfigReport* report) {
  int pilots = 0;
  std::map<std::string, drive::PilotRole::Role> table;
  for (const drive::PilotRole& role : config.drive().roles()) {
    table[role.client_id()] = role.role();
    if (role.role() == drive::PilotRole::PILOT) ++pilots;
    if (role.client_id().find("CHANGE-ME") != std::string::npos) {
      report->Fail("role table: '" + role.client_id() + "' is a placeholder",
                   "put the certificate names of your operators in drive.roles (make_pki.sh "
                   "--pilot NAME / --relay NAME), or remove the line");
    }
  }
  if (pilots == 0) {
    report->Fail("role table: no PILOT, so nobody may drive",
                 "add roles { client_id: \"NAME\" role: PILOT strength: 10 } to the drive "
                 "section, NAME being a pilot certificate's name");
  }
  if (!pki_roles) return;
  bool consistent = true;
  for (const auto& [name, role] : table) {
    if (name.find("CHANGE-ME") != std::string::npos) continue;
    const auto issued = pki_roles->find(name);
    if (issued != pki_roles->end() && issued->second == "revoked") {
      report->Fail(
          "role table: '" + name +
              "' was revoked (its certificate is in the CRL), so nobody can act as it",
          "remove the line, or issue the name again (make_pki.sh --" +
              std::string(table.at(name) == drive::PilotRole::PILOT ? "pilot " : "observer ") +
              name + ") and copy its bundle");
      consistent = false;
    } else if (issued == pki_roles->end()) {
      report->Fail(
          "role table: '" + name +
              "' has no certificate in this PKI, so nobody can "
              "act as it",
          "use the name of a certificate (make_pki.sh --" +
              std::string(table.at(name) == drive::PilotRole::PILOT ? "pilot " : "observer ") +
              name + " adds one), or remove the line");
      consistent = false;
    }
  }
  for (const auto& [name, role] : *pki_roles) {
    const auto it = table.find(name);
    if (role == "pilot" && (it == table.end() || it->second != drive::PilotRole::PILOT)) {
      report->Fail("'" + name +
                       "' holds a pilot certificate, but the role table does not list "
                       "it as a PILOT: it can only watch",
                   "add roles { client_id: \"" + name +
                       "\" role: PILOT strength: 10 } to the drive section");
      consistent = false;
    } else if (role == "relay" && it == table.end()) {
      report->Fail("the relay '" + name +
                       "' is not in the role table: e-stops of the observers "
                       "behind it are dropped",
                   "add roles { client_id: \"" + name + "\" role: OBSERVER } to the drive section");
      consistent = false;
    }
  }
  if (consistent) report->Ok("role table matches the PKI's certificates");
}

void CheckServerConfig(const ServerConfig& config, const std::string& config_dir,
                       const dds::ParticipantOptions& dds, ConfigReport* report) {
  CheckServerFiles(config, config_dir, report);
  const dds::ProfileCheck profile = dds::CheckDdsProfile(dds, "mostar", report);
  std::optional<std::map<std::string, std::string>> pki_roles;
  if (profile.secure && !profile.certificate_path.empty()) {
    const std::string path = DirectoryOf(profile.certificate_path) + "/roles";
    std::map<std::string, std::string> roles;
    std::string error;
    if (Exists(path) && ReadPkiRoles(path, &roles, &error)) {
      pki_roles = roles;
    } else if (Exists(path)) {
      report->Fail(error, "copy the robot's bundle again (make_pki.sh OUT_DIR/hosts/ROBOT/)");
    } else {
      report->Ok("no roles file beside " + profile.certificate_path +
                 ": role names not checked against the PKI (make_pki.sh puts it in the "
                 "robot's bundle)");
    }
  }
  CheckRoleTable(config, pki_roles, report);
}

}  // namespace mostar::server

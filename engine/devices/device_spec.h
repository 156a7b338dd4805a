#pragma once
// A tool's "device" field: where its pose comes from when it is not its scripted trajectory.
// "scripted" (the default) interpolates the trajectory; other types are made by factories the front
// end registers (register_device_type, engine/devices/device.h): "igtl" for an OpenIGTLink tracker
// or haptic device (engine/devices/igtl/igtl_device.h).
#include <string>

namespace xcut {

struct DeviceSpec {
    std::string type = "scripted";
    std::string field;             ///< "tools[i].device", for messages
    std::string file;              ///< the scene file, for messages
    std::string host;              ///< igtl: "" listens on `port` (a server, as 3D Slicer's clients expect)
    int port = 18944;              ///< igtl: the OpenIGTLink port
    std::string stream;            ///< igtl: the device name of the TRANSFORM stream; "" takes any
    double units = 1e-3;           ///< igtl: metres per unit of the translations received (mm, as trackers send)
    bool sync = false;             ///< igtl: each step waits for the pose stamped at its time (replays, tests)
    double timeout = 2.0;          ///< igtl sync: wait at most this long for a pose [s] of wall time
    double connect_timeout = 60.0; ///< igtl sync: wait at most this long for the peer to connect [s]
};

}  // namespace xcut

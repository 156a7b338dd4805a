// xcut-igtl-play: a tiny OpenIGTLink client, on the same library as xcut's device bridge
// (engine/devices/igtl/igtl_device.h). It plays a recorded trajectory (the CSV of `xcut run
// --record`, or a scene's trajectory_csv: time,x,y,z,qw,qx,qy,qz in metres) to a tool listening
// as {"device": {"type": "igtl"}} as TRANSFORM messages stamped with the trajectory's times, and
// prints the force messages (NDARRAY "<tool>_force") it gets back. docs/devices.md shows it in use.
//
//   xcut-igtl-play TRAJECTORY.csv [--host 127.0.0.1] [--port 18944] [--units mm] [--rate HZ]
//                  [--stream NAME] [--hold S] [--corrupt K] [--close-after K]
//
// --rate 0 sends every pose at once (a sync device takes them by their stamps); --hold keeps the
// connection S seconds after the last pose, reading forces; --corrupt and --close-after break the
// K-th message's CRC or drop the connection after K messages, to see the device hold the tool.
#include <igtlClientSocket.h>
#include <igtlMessageHeader.h>
#include <igtlNDArrayMessage.h>
#include <igtlTransformMessage.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

struct Pose {
    double t, p[3], q[4];  // [s], [m], w x y z
};

std::vector<Pose> read_csv(const char* path) {
    std::ifstream in(path);
    std::vector<Pose> out;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        if (line.empty() || line.rfind("time", 0) == 0) continue;
        for (char& c : line) c = c == ',' ? ' ' : c;
        std::istringstream w(line);
        Pose p;
        if (!(w >> p.t >> p.p[0] >> p.p[1] >> p.p[2] >> p.q[0] >> p.q[1] >> p.q[2] >> p.q[3])) {
            std::fprintf(stderr, "error: %s: line %d: expected time,x,y,z,qw,qx,qy,qz\n", path, n);
            std::exit(2);
        }
        out.push_back(p);
    }
    if (out.empty()) std::fprintf(stderr, "error: %s: no poses (a missing or empty file)\n", path), std::exit(2);
    return out;
}

/// Force messages arriving within the next 2 ms (the device sends them at up to 1 kHz).
void read_forces(igtl::ClientSocket* s, long& count, double last[6]) {
    s->SetReceiveTimeout(1);
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(2);
    while (std::chrono::steady_clock::now() < until) {
        igtl::MessageHeader::Pointer h = igtl::MessageHeader::New();
        h->InitPack();
        if (s->Receive(h->GetPackPointer(), h->GetPackSize()) != h->GetPackSize()) return;
        h->Unpack();
        s->SetReceiveTimeout(1000);
        if (std::strcmp(h->GetDeviceType(), "NDARRAY") != 0) {
            s->Skip(h->GetBodySizeToRead());
            continue;
        }
        igtl::NDArrayMessage::Pointer m = igtl::NDArrayMessage::New();
        m->SetMessageHeader(h);
        m->AllocatePack();
        s->Receive(m->GetPackBodyPointer(), m->GetPackBodySize());
        if (m->Unpack(1) & igtl::MessageBase::UNPACK_BODY) {
            if (m->GetArray() && m->GetArray()->GetRawArraySize() == 6 * sizeof(double))
                std::memcpy(last, m->GetArray()->GetRawArray(), 6 * sizeof(double));
            ++count;
        }
        s->SetReceiveTimeout(1);
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: xcut-igtl-play TRAJECTORY.csv [--host H] [--port P] [--units m|cm|mm] [--rate HZ] "
                             "[--stream NAME] [--hold S] [--corrupt K] [--close-after K]\n");
        return 2;
    }
    std::string host = "127.0.0.1", stream = "xcut-igtl-play";
    int port = 18944, corrupt = -1, close_after = -1;
    double units = 1e-3, rate = 0.0, hold = 0.0;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string k = argv[i], v = argv[i + 1];
        if (k == "--host") host = v;
        else if (k == "--port") port = std::atoi(v.c_str());
        else if (k == "--units") units = v == "m" ? 1.0 : v == "cm" ? 1e-2 : 1e-3;
        else if (k == "--rate") rate = std::atof(v.c_str());
        else if (k == "--stream") stream = v;
        else if (k == "--hold") hold = std::atof(v.c_str());
        else if (k == "--corrupt") corrupt = std::atoi(v.c_str());
        else if (k == "--close-after") close_after = std::atoi(v.c_str());
        else return std::fprintf(stderr, "error: unknown option %s\n", k.c_str()), 2;
    }
    const std::vector<Pose> poses = read_csv(argv[1]);
    igtl::ClientSocket::Pointer socket = igtl::ClientSocket::New();
    for (int tries = 0; socket->ConnectToServer(host.c_str(), port) != 0; ++tries) {
        if (tries >= 100) return std::fprintf(stderr, "error: cannot connect to %s:%d\n", host.c_str(), port), 1;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    long forces = 0;
    double last[6] = {0, 0, 0, 0, 0, 0};
    const auto start = std::chrono::steady_clock::now();
    for (size_t i = 0; i < poses.size(); ++i) {
        if (close_after >= 0 && static_cast<int>(i) >= close_after) break;
        const Pose& p = poses[i];
        if (rate > 0.0) std::this_thread::sleep_until(start + std::chrono::duration<double>(i / rate));
        const Eigen::Matrix3d r = Eigen::Quaterniond(p.q[0], p.q[1], p.q[2], p.q[3]).normalized().toRotationMatrix();
        igtl::Matrix4x4 m;
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) m[a][b] = a == 3 ? (b == 3 ? 1.f : 0.f) : b == 3 ? float(p.p[a] / units) : float(r(a, b));
        igtl::TransformMessage::Pointer msg = igtl::TransformMessage::New();
        msg->SetDeviceName(stream.c_str());
        const double sec = std::floor(p.t);
        msg->SetTimeStamp(static_cast<unsigned>(sec), static_cast<unsigned>(std::llround((p.t - sec) * 4294967296.0)));
        msg->SetMatrix(m);
        msg->Pack();
        if (static_cast<int>(i) == corrupt) static_cast<unsigned char*>(msg->GetPackBodyPointer())[0] ^= 0xff;
        if (socket->Send(msg->GetPackPointer(), msg->GetPackSize()) == 0) {
            std::fprintf(stderr, "error: the connection closed after %zu poses\n", i);
            return 1;
        }
        read_forces(socket, forces, last);
    }
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(hold);
    while (std::chrono::steady_clock::now() < until) {
        read_forces(socket, forces, last);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    socket->CloseSocket();
    std::printf("sent %zu poses; %ld force messages back, the last F = (%.6g, %.6g, %.6g) N\n",
                close_after >= 0 ? std::min<size_t>(poses.size(), close_after) : poses.size(), forces, last[0], last[1], last[2]);
    return 0;
}

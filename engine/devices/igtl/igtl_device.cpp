#include "engine/devices/igtl/igtl_device.h"

#include "engine/trajectory.h"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <igtlMessageHeader.h>
#include <igtlNDArrayMessage.h>
#include <igtlPositionMessage.h>
#include <igtlTransformMessage.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cerrno>
#include <cstring>

#include "engine/error.h"

namespace xcut {

namespace {

constexpr int kMaxBody = 1 << 20;  // a pose is 48 bytes; anything this large is not ours [bytes]

double wall_now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// Waits up to 100 ms for `fd` to be readable; true if it is.
bool readable(int fd) {
    pollfd p{fd, POLLIN, 0};
    return ::poll(&p, 1, 100) > 0;
}

int listen_on(const DeviceSpec& spec) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    const int on = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof(on));
    sockaddr_in addr{};
    addr.sin_family = AF_INET, addr.sin_port = htons(static_cast<uint16_t>(spec.port)), addr.sin_addr.s_addr = INADDR_ANY;
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 || ::listen(fd, 1) != 0) {
        const std::string why = std::strerror(errno);
        if (fd >= 0) ::close(fd);
        throw InputError(spec.file, spec.field + ".port", fmt::format("cannot listen on port {}: {}", spec.port, why));
    }
    return fd;
}

int connect_to(const DeviceSpec& spec) {
    addrinfo hints{}, *found = nullptr;
    hints.ai_family = AF_INET, hints.ai_socktype = SOCK_STREAM;
    if (::getaddrinfo(spec.host.c_str(), std::to_string(spec.port).c_str(), &hints, &found) != 0 || !found) return -1;
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    const bool ok = fd >= 0 && ::connect(fd, found->ai_addr, found->ai_addrlen) == 0;
    ::freeaddrinfo(found);
    if (!ok && fd >= 0) ::close(fd);
    return ok ? fd : -1;
}

/// A TRANSFORM's matrix or a POSITION's quaternion as a pose; false if it is not a rigid motion.
bool to_pose(const Eigen::Matrix3d& r, const Vec3& p, Keyframe& k) {
    if (!r.allFinite() || !p.allFinite() || (r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-3 ||
        r.determinant() < 0.0)
        return false;
    k.orientation = Eigen::Quaterniond(r).normalized();
    k.position = p;
    return true;
}

}  // namespace

IgtlDevice::IgtlDevice(const DeviceSpec& spec, const std::string& tool, const Keyframe& start)
    : LiveDevice(start, "igtl"), spec_(spec), tool_(tool) {
    if (spec_.host.empty()) listener_ = listen_on(spec_);
    thread_ = std::thread([this] { serve(); });
}

IgtlDevice::~IgtlDevice() {
    quit_ = true;
    arrived_.notify_all();
    thread_.join();
    if (listener_ >= 0) ::close(listener_);
    const IgtlStats s = stats();
    fmt::print(stderr, "igtl tool {}: {} poses, {} other messages, {} malformed, {} connections ({} lost), {} waits timed "
                       "out, {} force messages\n",
               tool_, s.poses, s.ignored, s.malformed, s.connections, s.lost, s.timeouts, s.forces_sent);
}

IgtlStats IgtlDevice::stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return stats_;
}

void IgtlDevice::warn(const std::string& what, long& counter) {  // with mutex_ held
    if (counter++ == 0)
        fmt::print(stderr, "warning: igtl tool {}: {}; the tool holds still (further ones counted, not printed)\n", tool_, what);
}

bool IgtlDevice::read_fully(int fd, void* data, size_t size) {
    auto* at = static_cast<char*>(data);
    while (size > 0) {
        if (quit_) return false;
        if (!readable(fd)) continue;
        const ssize_t n = ::recv(fd, at, size, 0);
        if (n <= 0) return false;
        at += n, size -= static_cast<size_t>(n);
    }
    return true;
}

void IgtlDevice::take_pose(const Keyframe& k) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.poses;
    if (spec_.sync) {
        if (!received_.empty() && !(k.time > received_.back().time)) {
            warn(fmt::format("a pose stamped {} s after one stamped {} s (sync needs increasing stamps)", k.time,
                             received_.back().time), stats_.malformed);
            return;
        }
        received_.push_back(k);
        arrived_.notify_all();
    }
    set_target_locked(k.position, k.orientation);  // the newest target: live mode and the haptic loop
}

void IgtlDevice::serve() {
    while (!quit_) {
        int fd = -1;
        if (listener_ >= 0) {
            if (readable(listener_)) fd = ::accept(listener_, nullptr, nullptr);
        } else {
            fd = connect_to(spec_);
            if (fd < 0) std::this_thread::sleep_for(std::chrono::milliseconds(200));
        }
        if (fd < 0) continue;
        const int on = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof(on));
        {
            std::lock_guard<std::mutex> lock(mutex_);
            ++stats_.connections;
            stream_ended_ = false;
        }
        arrived_.notify_all();  // a sync step waiting for its first peer goes on
        peer_ = fd;
        std::string why;
        while (!quit_ && why.empty()) {
            igtl::MessageHeader::Pointer header = igtl::MessageHeader::New();
            header->InitPack();
            if (!read_fully(fd, header->GetPackPointer(), header->GetPackSize())) break;
            header->Unpack();
            const int body = header->GetBodySizeToRead();
            const std::string type = header->GetDeviceType(), name = header->GetDeviceName();
            if (body < 0 || body > kMaxBody) {
                why = fmt::format("a malformed message (type \"{}\", body of {} bytes): the connection is dropped", type, body);
                break;
            }
            igtl::MessageBase::Pointer msg;
            const bool pose = (type == "TRANSFORM" || type == "POSITION") && (spec_.stream.empty() || spec_.stream == name);
            if (type == "TRANSFORM" && pose) msg = igtl::TransformMessage::New();
            else if (type == "POSITION" && pose) msg = igtl::PositionMessage::New();
            else msg = igtl::MessageBase::New();
            msg->SetMessageHeader(header);
            msg->AllocatePack();
            if (!read_fully(fd, msg->GetPackBodyPointer(), static_cast<size_t>(msg->GetPackBodySize()))) break;
            if (!pose) {
                std::lock_guard<std::mutex> lock(mutex_);
                ++stats_.ignored;
                continue;
            }
            Keyframe k;
            unsigned sec = 0, frac = 0;
            msg->GetTimeStamp(&sec, &frac);
            k.time = sec + frac / 4294967296.0;
            bool ok = (msg->Unpack(1) & igtl::MessageBase::UNPACK_BODY) != 0;
            if (ok && type == "TRANSFORM") {
                igtl::Matrix4x4 m;
                static_cast<igtl::TransformMessage*>(msg.GetPointer())->GetMatrix(m);
                Eigen::Matrix3d r;
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j) r(i, j) = m[i][j];
                ok = to_pose(r, Vec3(m[0][3], m[1][3], m[2][3]) * spec_.units, k);
            } else if (ok) {
                float p[3], q[4];
                auto* pm = static_cast<igtl::PositionMessage*>(msg.GetPointer());
                pm->GetPosition(p), pm->GetQuaternion(q);
                const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
                ok = quat.norm() > 0.5 && to_pose(quat.normalized().toRotationMatrix(), Vec3(p[0], p[1], p[2]) * spec_.units, k);
            }
            if (ok) {
                take_pose(k);
            } else {
                std::lock_guard<std::mutex> lock(mutex_);
                warn(fmt::format("a malformed {} message from \"{}\" (CRC or not a rigid motion) was dropped", type, name),
                     stats_.malformed);
            }
        }
        peer_ = -1;
        ::close(fd);
        std::lock_guard<std::mutex> lock(mutex_);
        if (!why.empty()) warn(why, stats_.malformed);
        if (!quit_) warn("the connection was lost or closed; waiting for the peer to connect again", stats_.lost);
        stream_ended_ = true;
        arrived_.notify_all();
    }
}

Keyframe IgtlDevice::pose(double t) {
    if (!spec_.sync) return LiveDevice::pose(t);
    std::unique_lock<std::mutex> lock(mutex_);
    // In sync the run keeps the peer's time: it waits for the peer to connect (two processes started
    // apart), then for each step's pose; a peer that never comes or stops sending mid-stream stops the
    // run with this message rather than letting the tool hold still and the two drift apart. A stream
    // that ended (the peer closed it) holds the tool at its last pose, as a finished recording does.
    if (stats_.connections == 0 && !quit_) {
        fmt::print(stderr, "igtl tool {}: waiting for the OpenIGTLink peer ({}; sync: at most {} s)\n", tool_,
                   spec_.host.empty() ? fmt::format("listening on port {}", spec_.port)
                                      : fmt::format("connecting to {}:{}", spec_.host, spec_.port),
                   spec_.connect_timeout);
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(spec_.connect_timeout);
        while (stats_.connections == 0 && !quit_)
            if (arrived_.wait_until(lock, until) == std::cv_status::timeout && stats_.connections == 0)
                throw InputError(spec_.file, spec_.field + ".connect_timeout",
                                 fmt::format("no OpenIGTLink peer connected within {} s (start the sender, or raise "
                                             "connect_timeout)", spec_.connect_timeout));
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(spec_.timeout);
    while ((received_.empty() || received_.back().time < t) && !stream_ended_ && !quit_) {
        if (arrived_.wait_until(lock, deadline) == std::cv_status::timeout) {
            ++stats_.timeouts;
            throw InputError(spec_.file, spec_.field + ".timeout",
                             fmt::format("no pose stamped at {} s arrived within {} s of wall time (the last was stamped "
                                         "{} s): the peer is behind or stopped; sync stops the run rather than let the "
                                         "tool and the stream drift apart (raise timeout to wait longer)",
                                         t, spec_.timeout, received_.empty() ? 0.0 : received_.back().time));
        }
    }
    if (received_.empty()) {
        Keyframe k = target_locked();
        k.time = t;
        return k;
    }
    return sample_trajectory(received_, t);
}

void IgtlDevice::render_force(const Vec3& force, const Vec3& torque) {
    ForceKeepingDevice::render_force(force, torque);
    const int fd = peer_;
    if (fd < 0) return;
    std::lock_guard<std::mutex> lock(send_mutex_);
    const double now = wall_now();
    if (now - last_send_ < 1.0 / force_rate) return;
    last_send_ = now;
    double values[6] = {force.x(), force.y(), force.z(), torque.x(), torque.y(), torque.z()};
    igtl::Array<igtlFloat64> array;
    igtl::ArrayBase::IndexType size(1, 6);
    array.SetSize(size);
    array.SetArray(values);
    igtl::NDArrayMessage::Pointer msg = igtl::NDArrayMessage::New();
    msg->SetDeviceName((tool_ + "_force").c_str());
    msg->SetArray(igtl::NDArrayMessage::TYPE_FLOAT64, &array);
    msg->Pack();
    if (::send(fd, msg->GetPackPointer(), static_cast<size_t>(msg->GetPackSize()), MSG_NOSIGNAL) ==
        static_cast<ssize_t>(msg->GetPackSize())) {
        std::lock_guard<std::mutex> l(mutex_);
        ++stats_.forces_sent;
    }
}

void register_igtl_device() {
    register_device_type("igtl", [](const DeviceSpec& spec, const std::string& tool, const Keyframe& start) {
        return std::make_unique<IgtlDevice>(spec, tool, start);
    });
}

}  // namespace xcut

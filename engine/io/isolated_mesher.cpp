#include "engine/io/isolated_mesher.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fmt/format.h>

#include "engine/error.h"

namespace xcut {

namespace {

template <class T>
void put(std::string& out, const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
void put_text(std::string& out, const std::string& s) {
    put<uint64_t>(out, s.size());
    out += s;
}

/// Reads what the child wrote, in order; any shortfall is a broken child.
class Reader {
public:
    explicit Reader(const std::string& data) : data_(data) {}
    template <class T>
    T get() {
        T v{};
        if (data_.size() - at_ < sizeof(T)) throw std::runtime_error("short");
        std::memcpy(&v, data_.data() + at_, sizeof(T));
        at_ += sizeof(T);
        return v;
    }
    std::string text() {
        const uint64_t n = get<uint64_t>();
        if (data_.size() - at_ < n) throw std::runtime_error("short");
        std::string s = data_.substr(at_, n);
        at_ += n;
        return s;
    }

private:
    const std::string& data_;
    size_t at_ = 0;
};

void write_all(int fd, const std::string& data) {
    size_t done = 0;
    while (done < data.size()) {
        const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;
        done += static_cast<size_t>(n);
    }
}

/// The child: runs the mesher, writes "M" + the mesh or "E" + the error.
[[noreturn]] void child(int fd, const std::function<MeshData()>& mesh) {
    // A fatal signal ends the child at once, as the parent expects: not through a handler the
    // process installed (a sanitizer's or a fuzzer's reports and symbolizes, slowly, a crash that
    // is the mesher's). The mesher's own assertion text would only repeat what the parent says.
    for (int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, SIG_DFL);
    const int devnull = ::open("/dev/null", O_WRONLY);
    if (devnull >= 0) ::dup2(devnull, STDERR_FILENO), ::close(devnull);
    std::string out;
    try {
        const MeshData m = mesh();
        out = "M";
        put<uint64_t>(out, m.points.size());
        for (const auto& p : m.points) put(out, p.x()), put(out, p.y()), put(out, p.z());
        put<uint64_t>(out, m.cells.size());
        for (const auto& c : m.cells)
            for (int v : c) put<int32_t>(out, v);
    } catch (const InputError& e) {
        out = "E";
        put_text(out, e.file()), put_text(out, e.field()), put_text(out, e.message());
    } catch (const std::exception& e) {
        out = "E";
        put_text(out, ""), put_text(out, "surface"), put_text(out, e.what());
    }
    write_all(fd, out);
    ::close(fd);
    ::_exit(0);
}

/// The child's reply: the mesh, or the InputError it threw, thrown here.
MeshData read_reply(const std::string& path, const std::string& data) {
    std::string file, field, message;
    MeshData m;
    try {
        Reader r(data);
        if (r.get<char>() == 'E') {
            file = r.text(), field = r.text(), message = r.text();
        } else {
            m.source = path;
            const uint64_t n = r.get<uint64_t>();
            if (n > data.size() / 24) throw std::runtime_error("short");
            m.points.resize(n);
            for (auto& p : m.points) p.x() = r.get<double>(), p.y() = r.get<double>(), p.z() = r.get<double>();
            const uint64_t cells = r.get<uint64_t>();
            if (cells > data.size() / 16) throw std::runtime_error("short");
            m.cells.resize(cells);
            for (auto& c : m.cells)
                for (int& v : c) v = r.get<int32_t>();
        }
    } catch (const std::runtime_error&) {
        throw InputError(path, "surface", "the mesher's result was cut short");
    }
    if (!field.empty()) throw InputError(file.empty() ? path : file, field, message);  // the child's own error
    return m;
}

}  // namespace

MeshData run_isolated_mesher(const std::string& path, const std::function<MeshData()>& mesh) {
    int fds[2];
    if (::pipe(fds) != 0) throw InputError(path, "surface", fmt::format("cannot start the mesher: {}", std::strerror(errno)));
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]), ::close(fds[1]);
        throw InputError(path, "surface", fmt::format("cannot start the mesher: {}", std::strerror(errno)));
    }
    if (pid == 0) {
        ::close(fds[0]);
        child(fds[1], mesh);
    }
    ::close(fds[1]);
    std::string data;
    char buffer[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        data.append(buffer, static_cast<size_t>(n));
    }
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(status) || data.empty())
        throw InputError(path, "surface",
                         fmt::format("TetGen aborted on this surface ({}): it is nearly degenerate or intersects itself; "
                                     "repair it (gmsh, MeshLab) or remesh it",
                                     WIFSIGNALED(status) ? strsignal(WTERMSIG(status)) : "no result"));
    return read_reply(path, data);
}

}  // namespace xcut

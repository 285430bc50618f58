#include "Link/LinkPort.h"
#include "Core/Errors.h"
#include <libserialport.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <glob.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

namespace armadillo::link {

namespace {

timespec toTimespec(double seconds)
{
    seconds = std::clamp(seconds, 0.0, 3600.0);
    timespec ts {};
    ts.tv_sec = static_cast<time_t>(seconds);
    ts.tv_nsec = static_cast<long>((seconds - static_cast<double>(ts.tv_sec)) * 1e9);
    return ts;
}

std::string errnoText(int e) { return std::strerror(e); }

speed_t termiosSpeed(int baud)
{
    switch (baud) {
    case 1200: return B1200;
    case 2400: return B2400;
    case 4800: return B4800;
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 500000: return B500000;
    case 921600: return B921600;
    case 1000000: return B1000000;
    case 2000000: return B2000000;
    default: return B0;
    }
}

} // namespace

bool isStandardBaud(int baud) noexcept { return termiosSpeed(baud) != B0; }

// --- FdPort ------------------------------------------------------------------------------------

FdPort::~FdPort() { FdPort::close(); }

void FdPort::adopt(int fd, bool owned)
{
    fd_ = fd;
    owned_ = owned;
    struct stat st {};
    socket_ = ::fstat(fd, &st) == 0 && S_ISSOCK(st.st_mode);
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags >= 0) ::fcntl(fd, F_SETFL, flags | O_NONBLOCK);
}

void FdPort::close() noexcept
{
    if (fd_ >= 0) releaseDevice(fd_);
    if (fd_ >= 0 && owned_) ::close(fd_);
    fd_ = -1;
    closeBackend();
}

std::size_t FdPort::read(std::uint8_t* buffer, std::size_t capacity, double timeout)
{
    if (fd_ < 0) throw core::IoError("port " + name() + " is not open");
    pollfd p {fd_, POLLIN, 0};
    const timespec ts = toTimespec(timeout);
    const int r = ::ppoll(&p, 1, &ts, nullptr);
    if (r < 0) {
        if (errno == EINTR) return 0;
        throw core::IoError("port " + name() + ": poll failed: " + errnoText(errno));
    }
    if (r == 0) return 0;
    if (p.revents & POLLIN) {
        const ssize_t n = ::read(fd_, buffer, capacity);
        if (n > 0) return static_cast<std::size_t>(n);
        if (n == 0) throw core::IoError("port " + name() + " closed by the other side");
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return 0;
        throw core::IoError("port " + name() + " disconnected: " + errnoText(errno));
    }
    if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) throw core::IoError("port " + name() + " disconnected (hang-up)");
    return 0;
}

std::size_t FdPort::write(const std::uint8_t* bytes, std::size_t count)
{
    if (fd_ < 0) throw core::IoError("port " + name() + " is not open");
    std::size_t done = 0;
    int waits = 0;
    while (done < count) {
        const ssize_t n = socket_ ? ::send(fd_, bytes + done, count - done, MSG_NOSIGNAL | MSG_DONTWAIT)
                                  : ::write(fd_, bytes + done, count - done);
        if (n > 0) {
            done += static_cast<std::size_t>(n);
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            // The output buffer is full (a device that stopped reading): wait a little, then drop.
            if (++waits > 2) break;
            pollfd p {fd_, POLLOUT, 0};
            const timespec ts = toTimespec(0.002);
            if (::ppoll(&p, 1, &ts, nullptr) < 0 && errno != EINTR)
                throw core::IoError("port " + name() + ": poll failed: " + errnoText(errno));
            if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) throw core::IoError("port " + name() + " disconnected (hang-up)");
            continue;
        }
        throw core::IoError("port " + name() + " disconnected: " + (n < 0 ? errnoText(errno) : std::string("write returned 0")));
    }
    return done;
}

// --- SerialPort --------------------------------------------------------------------------------

SerialPort::SerialPort(std::string path, int baud, Backend backend) : path_(std::move(path)), baud_(baud), wanted_(backend)
{
    if (baud_ <= 0) throw core::IoError("port " + path_ + ": baud rate must be positive, not " + std::to_string(baud_));
}

SerialPort::~SerialPort() { FdPort::close(); }

namespace {

/// Takes the device for this process (see SerialPort in LinkPort.h). False with the reason when
/// another program holds it.
bool takeDevice(int fd, std::string& why)
{
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
        why = errno == EWOULDBLOCK ? "in use by another program (it holds a lock on the device)" : "cannot lock it: " + errnoText(errno);
        return false;
    }
    ::ioctl(fd, TIOCEXCL);   // best effort: some tty drivers refuse it; the flock still holds
    return true;
}

} // namespace

void SerialPort::releaseDevice(int fd) noexcept
{
    ::ioctl(fd, TIOCNXCL);
    ::flock(fd, LOCK_UN);
}

void SerialPort::closeBackend() noexcept
{
    if (spPort_) {
        auto* port = static_cast<sp_port*>(spPort_);
        sp_close(port);
        sp_free_port(port);
        spPort_ = nullptr;
    }
    backendName_.clear();
}

bool SerialPort::openWithLibSerialPort(std::string& why)
{
    sp_port* port = nullptr;
    if (sp_get_port_by_name(path_.c_str(), &port) != SP_OK || !port) {
        why = "libserialport does not know it";
        return false;
    }
    auto fail = [&](const char* what) {
        char* msg = sp_last_error_message();
        why = std::string(what) + (msg ? std::string(": ") + msg : std::string());
        if (msg) sp_free_error_message(msg);
        sp_close(port);
        sp_free_port(port);
        return false;
    };
    if (sp_open(port, SP_MODE_READ_WRITE) != SP_OK) {
        char* msg = sp_last_error_message();
        why = std::string("libserialport cannot open it") + (msg ? std::string(": ") + msg : std::string());
        if (msg) sp_free_error_message(msg);
        sp_free_port(port);
        return false;
    }
    if (sp_set_baudrate(port, baud_) != SP_OK) return fail("cannot set the baud rate");
    if (sp_set_bits(port, 8) != SP_OK || sp_set_parity(port, SP_PARITY_NONE) != SP_OK ||
        sp_set_stopbits(port, 1) != SP_OK || sp_set_flowcontrol(port, SP_FLOWCONTROL_NONE) != SP_OK)
        return fail("cannot set 8N1 without flow control");
    int fd = -1;
    if (sp_get_port_handle(port, &fd) != SP_OK || fd < 0) return fail("no file descriptor");
    if (std::string taken; !takeDevice(fd, taken)) {
        sp_close(port);
        sp_free_port(port);
        throw core::IoError("port " + path_ + ": " + taken);
    }
    sp_flush(port, SP_BUF_BOTH);
    spPort_ = port;
    adopt(fd, false);   // libserialport closes it in sp_close
    backendName_ = "libserialport";
    return true;
}

void SerialPort::openWithTermios()
{
    const int fd = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw core::IoError("cannot open port " + path_ + ": " + errnoText(errno));
    auto fail = [&](const std::string& what) {
        const int e = errno;
        ::close(fd);
        throw core::IoError("port " + path_ + ": " + what + (e ? ": " + errnoText(e) : std::string()));
    };
    if (!::isatty(fd)) {
        errno = 0;
        fail("not a serial port (not a tty)");
    }
    termios tio {};
    if (::tcgetattr(fd, &tio) != 0) fail("cannot read its settings");
    ::cfmakeraw(&tio);
    tio.c_cflag |= CLOCAL | CREAD;
    tio.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CSIZE);
    tio.c_cflag |= CS8;
#ifdef CRTSCTS
    tio.c_cflag &= ~static_cast<tcflag_t>(CRTSCTS);
#endif
    tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
    tio.c_cc[VMIN] = 0;
    tio.c_cc[VTIME] = 0;
    const speed_t speed = termiosSpeed(baud_);
    if (speed == B0) {
        errno = 0;
        fail("baud rate " + std::to_string(baud_) + " is not a standard rate (the termios path supports 1200…2000000 standard rates)");
    }
    ::cfsetispeed(&tio, speed);
    ::cfsetospeed(&tio, speed);
    if (::tcsetattr(fd, TCSANOW, &tio) != 0) fail("cannot apply 8N1 raw settings");
    if (std::string taken; !takeDevice(fd, taken)) {
        ::close(fd);
        throw core::IoError("port " + path_ + ": " + taken);
    }
    ::tcflush(fd, TCIOFLUSH);
    adopt(fd, true);
    backendName_ = "termios";
}

void SerialPort::open()
{
    if (isOpen()) return;
    struct stat st {};
    if (::stat(path_.c_str(), &st) != 0) throw core::IoError("no serial port " + path_ + ": " + errnoText(errno));
    std::string why;
    if (wanted_ != Backend::Termios) {
        if (openWithLibSerialPort(why)) return;
        if (wanted_ == Backend::LibSerialPort) throw core::IoError("port " + path_ + ": " + why);
    }
    openWithTermios();
}

// --- Enumeration -------------------------------------------------------------------------------

std::vector<PortInfo> listSerialPorts()
{
    std::vector<PortInfo> out;
    sp_port** list = nullptr;
    const sp_return r = sp_list_ports(&list);
    if (r != SP_OK) {
        char* msg = sp_last_error_message();
        const std::string text = msg ? msg : "unknown error";
        if (msg) sp_free_error_message(msg);
        throw core::IoError("cannot list serial ports: " + text);
    }
    for (sp_port** p = list; p && *p; ++p) {
        PortInfo info;
        auto str = [](const char* s) { return s ? std::string(s) : std::string(); };
        info.name = str(sp_get_port_name(*p));
        info.description = str(sp_get_port_description(*p));
        switch (sp_get_port_transport(*p)) {
        case SP_TRANSPORT_USB: {
            info.transport = "usb";
            int vid = -1, pid = -1;
            if (sp_get_port_usb_vid_pid(*p, &vid, &pid) == SP_OK) {
                info.usbVid = vid;
                info.usbPid = pid;
            }
            info.manufacturer = str(sp_get_port_usb_manufacturer(*p));
            info.product = str(sp_get_port_usb_product(*p));
            info.serial = str(sp_get_port_usb_serial(*p));
            break;
        }
        case SP_TRANSPORT_BLUETOOTH:
            info.transport = "bluetooth";
            info.bluetoothAddress = str(sp_get_port_bluetooth_address(*p));
            break;
        default: info.transport = "native"; break;
        }
        out.push_back(std::move(info));
    }
    sp_free_port_list(list);
    // Bound RFCOMM ports have no sysfs device, so libserialport does not list them.
    glob_t g {};
    if (::glob("/dev/rfcomm*", 0, nullptr, &g) == 0) {
        for (std::size_t i = 0; i < g.gl_pathc; ++i) {
            const std::string name = g.gl_pathv[i];
            if (std::none_of(out.begin(), out.end(), [&](const PortInfo& x) { return x.name == name; }))
                {
                PortInfo info;
                info.name = name;
                info.description = "Bluetooth RFCOMM serial (opened with termios)";
                info.transport = "rfcomm";
                out.push_back(std::move(info));
            }
        }
    }
    ::globfree(&g);
    std::sort(out.begin(), out.end(), [](const PortInfo& a, const PortInfo& b) { return a.name < b.name; });
    return out;
}

} // namespace armadillo::link

#pragma once
// Byte transports under the host link: real serial ports (libserialport, or plain POSIX termios
// for ttys libserialport refuses — pseudo-terminals, /dev/rfcomm* Bluetooth ports), and the
// in-process simulator. A port can be closed and opened again: that is how the link reconnects.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::link {

class LinkPort {
public:
    virtual ~LinkPort() = default;
    virtual std::string name() const = 0;
    /// "libserialport", "termios" or "simulator" once open; "" before.
    virtual std::string backend() const = 0;
    /// Opens (again). Throws IoError naming the port when it is not there or cannot be set up.
    virtual void open() = 0;
    virtual void close() noexcept = 0;
    virtual bool isOpen() const noexcept = 0;
    /// Waits up to `timeout` seconds for input and reads what is there (at most `capacity`).
    /// Returns 0 on timeout. Throws IoError when the port went away (unplug, hang-up).
    virtual std::size_t read(std::uint8_t* buffer, std::size_t capacity, double timeout) = 0;
    /// Writes without blocking for long: bytes the port cannot take within a few milliseconds are
    /// dropped (the link's resync recovers). Returns the bytes written. Throws IoError when gone.
    virtual std::size_t write(const std::uint8_t* bytes, std::size_t count) = 0;
};

/// A port over a file descriptor (poll + read/write), shared by every fd-based backend.
class FdPort : public LinkPort {
public:
    ~FdPort() override;
    bool isOpen() const noexcept override { return fd_ >= 0; }
    std::size_t read(std::uint8_t* buffer, std::size_t capacity, double timeout) override;
    std::size_t write(const std::uint8_t* bytes, std::size_t count) override;
    void close() noexcept override;
    int fd() const noexcept { return fd_; }

protected:
    /// Takes ownership of fd (made non-blocking); `owned` false when a library closes it.
    void adopt(int fd, bool owned);
    virtual void closeBackend() noexcept {}
    /// Called with the still-open descriptor just before it is closed.
    virtual void releaseDevice(int) noexcept {}
    int fd_ = -1;
    bool owned_ = true;
    bool socket_ = false;   // sockets are written with MSG_NOSIGNAL: a closed peer is an error, not SIGPIPE
};

/// Standard baud rates the termios path supports (the libserialport path accepts any the
/// driver does).
bool isStandardBaud(int baud) noexcept;

/// A serial port by path. open() tries libserialport first and falls back to plain termios
/// when libserialport refuses the port but it is a tty (Debian's libserialport 0.1.1 refuses
/// pseudo-terminals and /dev/rfcomm*, which have no sysfs device). 8N1, no flow control.
/// The open device is marked as taken for other programs: an exclusive flock() on it (what
/// other serial tools check; a second ARMadillo gets "in use") and TIOCEXCL (further open()s
/// fail with EBUSY, except for root). Both end when the port is closed.
class SerialPort final : public FdPort {
public:
    enum class Backend { Auto, LibSerialPort, Termios };
    explicit SerialPort(std::string path, int baud = 57600, Backend backend = Backend::Auto);
    ~SerialPort() override;
    std::string name() const override { return path_; }
    std::string backend() const override { return backendName_; }
    void open() override;

private:
    void closeBackend() noexcept override;
    void releaseDevice(int fd) noexcept override;
    bool openWithLibSerialPort(std::string& why);
    void openWithTermios();
    std::string path_;
    int baud_;
    Backend wanted_;
    std::string backendName_;
    void* spPort_ = nullptr;   // struct sp_port*, kept out of the header
};

struct PortInfo {
    std::string name;          ///< /dev/ttyUSB0 …
    std::string description;
    std::string transport;     ///< "usb", "bluetooth", "native", "rfcomm"
    int usbVid = -1, usbPid = -1;
    std::string manufacturer, product, serial, bluetoothAddress;
};
/// Serial ports libserialport finds, plus /dev/rfcomm* Bluetooth ports it does not list.
/// Throws IoError when enumeration itself fails.
std::vector<PortInfo> listSerialPorts();

} // namespace armadillo::link

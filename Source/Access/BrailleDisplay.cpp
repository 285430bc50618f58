#include "Access/BrailleDisplay.h"
#include <cstdint>
#include <dlfcn.h>
#include <fstream>

namespace armadillo::access {

namespace {

/// brltty's BrlAPI, loaded at run time. Types and constants as brlapi.h / brlapi_keycodes.h
/// (brltty 6.5) define them: brlapi_connectionSettings_t {const char* auth; const char* host;},
/// BRLAPI_TTY_DEFAULT −1, BRLAPI_CURSOR_OFF 0, brlapi_keyCode_t uint64_t, key type mask
/// 0xE0000000 (type SYM = 0), code mask 0x1FFFFFFF, SYM_UNICODE 0x01000000, LINEFEED (Enter)
/// 0xFF0D, BACKSPACE 0xFF08.
class BrlApiDisplay final : public BrailleDisplay {
public:
    static std::unique_ptr<BrailleDisplay> open(const std::string& host, std::string& why)
    {
        void* lib = ::dlopen("libbrlapi.so.0.8", RTLD_NOW | RTLD_LOCAL);
        if (!lib) {
            why = "libbrlapi.so.0.8 not found (Debian: libbrlapi0.8)";
            return nullptr;
        }
        auto d = std::unique_ptr<BrlApiDisplay>(new BrlApiDisplay(lib));
        if (!d->open_ || !d->close_ || !d->enter_ || !d->leave_ || !d->writeText_ || !d->readKey_) {
            why = "libbrlapi.so.0.8 lacks the expected functions";
            return nullptr;
        }
        Settings s {nullptr, host.empty() ? nullptr : host.c_str()};
        d->fd_ = d->open_(&s, nullptr);
        if (d->fd_ < 0) {
            why = "no BrlAPI server (brltty) to connect to" + (host.empty() ? std::string() : " at " + host);
            return nullptr;
        }
        d->connected_ = true;
        // The controlling tty (found from $WINDOWPATH, $CONTROLVT or the process's own
        // virtual console); a session with none (ssh, a service) takes the root of brltty's tty
        // tree instead (an empty tty path).
        if (d->enter_(-1 /* BRLAPI_TTY_DEFAULT */, nullptr) < 0 && (!d->enterPath_ || d->enterPath_(nullptr, 0, nullptr) < 0)) {
            why = "BrlAPI refused tty mode";
            return nullptr;
        }
        d->tty_ = true;
        return d;
    }
    ~BrlApiDisplay() override
    {
        if (tty_ && !lost_) leave_();   // nothing to tell a server that is gone
        if (connected_) close_();
        ::dlclose(lib_);
    }
    void write(const std::string& text) override { writeText_(0 /* BRLAPI_CURSOR_OFF */, text.c_str()); }
    std::string readKey() override
    {
        std::uint64_t code = 0;
        const int got = readKey_(0, &code);
        if (got < 0) lost_ = true;   // end of file or an error on the connection
        if (got != 1) return "";
        if ((code & 0xE0000000ull) != 0) return "";   // a brltty command, not a typed key
        const std::uint64_t sym = code & 0x1FFFFFFFull;
        if (sym == 0xFF0D) return "\n";
        if (sym == 0xFF08) return "\b";
        std::uint32_t cp = 0;
        if ((sym & 0xFF000000ull) == 0x01000000ull) cp = static_cast<std::uint32_t>(sym & 0x00FFFFFFull);
        else if (sym < 0x100) cp = static_cast<std::uint32_t>(sym);
        else return "";
        std::string out;   // UTF-8
        if (cp < 0x80) out += static_cast<char>(cp);
        else if (cp < 0x800) {
            out += static_cast<char>(0xC0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        }
        return out;
    }
    int fd() const override { return fd_; }
    bool lost() const override { return lost_; }
    std::string name() const override { return "brlapi"; }

private:
    struct Settings {
        const char* auth;
        const char* host;
    };
    using OpenFn = int (*)(const Settings*, Settings*);
    using VoidFn = void (*)();
    using EnterFn = int (*)(int, const char*);
    using EnterPathFn = int (*)(int*, int, const char*);
    using IntFn = int (*)();
    using WriteFn = int (*)(int, const char*);
    using ReadKeyFn = int (*)(int, std::uint64_t*);
    explicit BrlApiDisplay(void* lib) : lib_(lib)
    {
        open_ = reinterpret_cast<OpenFn>(::dlsym(lib, "brlapi_openConnection"));
        close_ = reinterpret_cast<VoidFn>(::dlsym(lib, "brlapi_closeConnection"));
        enter_ = reinterpret_cast<EnterFn>(::dlsym(lib, "brlapi_enterTtyMode"));
        enterPath_ = reinterpret_cast<EnterPathFn>(::dlsym(lib, "brlapi_enterTtyModeWithPath"));
        leave_ = reinterpret_cast<IntFn>(::dlsym(lib, "brlapi_leaveTtyMode"));
        writeText_ = reinterpret_cast<WriteFn>(::dlsym(lib, "brlapi_writeText"));
        readKey_ = reinterpret_cast<ReadKeyFn>(::dlsym(lib, "brlapi_readKey"));
    }
    void* lib_ = nullptr;
    OpenFn open_ = nullptr;
    VoidFn close_ = nullptr;
    EnterFn enter_ = nullptr;
    EnterPathFn enterPath_ = nullptr;
    IntFn leave_ = nullptr;
    WriteFn writeText_ = nullptr;
    ReadKeyFn readKey_ = nullptr;
    int fd_ = -1;
    bool connected_ = false, tty_ = false, lost_ = false;
};

class CaptureDisplay final : public BrailleDisplay {
public:
    explicit CaptureDisplay(const std::string& path) : out_(path, std::ios::app) {}
    bool ok() const { return static_cast<bool>(out_); }
    void write(const std::string& text) override { out_ << "write: " << text << "\n" << std::flush; }
    std::string readKey() override { return ""; }
    int fd() const override { return -1; }
    std::string name() const override { return "capture"; }

private:
    std::ofstream out_;
};

} // namespace

std::unique_ptr<BrailleDisplay> makeBrailleDisplay(const std::string& spec, std::string& why)
{
    if (spec == "none") return nullptr;
    if (spec.rfind("capture:", 0) == 0) {
        auto c = std::make_unique<CaptureDisplay>(spec.substr(8));
        if (!c->ok()) {
            why = "cannot write " + spec.substr(8);
            return nullptr;
        }
        return c;
    }
    if (spec == "brlapi") return BrlApiDisplay::open("", why);
    if (spec.rfind("brlapi:", 0) == 0) return BrlApiDisplay::open(spec.substr(7), why);
    why = "unknown braille display '" + spec + "' (brlapi, brlapi:HOST, capture:FILE, none)";
    return nullptr;
}

} // namespace armadillo::access

#pragma once
// A fake BrlAPI server (brltty's braille display API) on a loopback TCP port, for tests: it speaks
// just enough of the protocol that libbrlapi's client side (brlapi_openConnection,
// brlapi_enterTtyMode, brlapi_writeText, brlapi_readKey, brlapi_leaveTtyMode) works against it,
// records every text written and sends keys typed "on the display". The protocol as brltty's
// Programs/brlapi_protocol.h and brlapi_client.c define it (protocol version 8): every packet is
// a header of two big-endian uint32 (payload size, type) and the payload; the server greets with
// VERSION ('v', uint32 8), the client echoes it, the server offers AUTH ('a', uint32 'N' = none);
// GETDISPLAYSIZE ('s') is answered with two uint32 (columns, rows); ENTERTTYMODE ('t') and
// LEAVETTYMODE ('L') with ACK ('A', empty); WRITE ('w') is uint32 flags then, in flag order,
// region (0x02: two uint32), text (0x04: uint32 size + bytes), attributes, cursor, charset; KEY
// ('k') carries the key code as two uint32 (high, low).
#include <arpa/inet.h>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <functional>
#include <mutex>
#include <netinet/in.h>
#include <poll.h>
#include <string>
#include <sys/socket.h>
#include <thread>
#include <unistd.h>
#include <vector>

namespace armadillo::test {

class FakeBrlApiServer {
public:
    static constexpr int kColumns = 40;

    FakeBrlApiServer()
    {
        listen_ = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a {};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = 0;
        if (::bind(listen_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(listen_, 1) != 0) return;
        socklen_t len = sizeof a;
        ::getsockname(listen_, reinterpret_cast<sockaddr*>(&a), &len);
        port_ = ntohs(a.sin_port);
        thread_ = std::thread([this] { run(); });
    }
    ~FakeBrlApiServer()
    {
        stop_ = true;
        if (thread_.joinable()) thread_.join();
        if (client_ >= 0) ::close(client_);
        ::close(listen_);
    }
    /// The BrlAPI host string: "127.0.0.1:N" means TCP port 4101 + N (brlapi.h: BRLAPI_SOCKETPORTNUM).
    std::string host() const { return "127.0.0.1:" + std::to_string(port_ - 4101); }
    bool ok() const { return port_ > 4101; }

    /// Every text written, spaces at the end removed, in order.
    std::vector<std::string> writes() const
    {
        std::lock_guard<std::mutex> l(mutex_);
        return writes_;
    }
    bool enteredTty() const { return enteredTty_.load(); }
    /// Keys typed on the display: characters (Latin-1) and '\n' for Enter (keysym 0xFF0D).
    void type(const std::string& keys)
    {
        std::lock_guard<std::mutex> l(mutex_);
        for (char c : keys) pendingKeys_.push_back(c == '\n' ? 0xFF0Du : static_cast<unsigned char>(c));
    }
    /// Called (on the server thread) for every text written: lets a test answer a prompt.
    void onWrite(std::function<void(const std::string&)> f)
    {
        std::lock_guard<std::mutex> l(mutex_);
        onWrite_ = std::move(f);
    }

private:
    void send(std::uint32_t type, const std::vector<std::uint32_t>& words)
    {
        std::vector<std::uint32_t> packet {htonl(static_cast<std::uint32_t>(4 * words.size())), htonl(type)};
        for (auto w : words) packet.push_back(htonl(w));
        (void)!::write(client_, packet.data(), 4 * packet.size());
    }
    bool readAll(void* buf, std::size_t n)
    {
        auto* p = static_cast<unsigned char*>(buf);
        while (n > 0) {
            pollfd f {client_, POLLIN, 0};
            if (::poll(&f, 1, 50) <= 0) {
                if (stop_) return false;
                continue;
            }
            const ssize_t r = ::read(client_, p, n);
            if (r <= 0) return false;
            p += r;
            n -= static_cast<std::size_t>(r);
        }
        return true;
    }
    void run()
    {
        while (!stop_) {
            pollfd f {listen_, POLLIN, 0};
            if (::poll(&f, 1, 50) > 0) break;
        }
        if (stop_) return;
        client_ = ::accept(listen_, nullptr, nullptr);
        send('v', {8});
        std::uint32_t header[2];
        std::vector<unsigned char> payload;
        auto packet = [&]() {
            if (!readAll(header, sizeof header)) return false;
            payload.assign(ntohl(header[0]), 0);
            return payload.empty() || readAll(payload.data(), payload.size());
        };
        if (!packet()) return;   // the client's VERSION
        send('a', {'N'});
        while (!stop_) {
            {   // keys typed meanwhile
                std::lock_guard<std::mutex> l(mutex_);
                for (std::uint32_t k : pendingKeys_) send('k', {0, k});
                pendingKeys_.clear();
            }
            pollfd f {client_, POLLIN, 0};
            if (::poll(&f, 1, 20) <= 0) continue;
            if (!packet()) return;
            switch (ntohl(header[1])) {
            case 's': send('s', {kColumns, 1}); break;
            case 't': enteredTty_ = true; send('A', {}); break;
            case 'L': send('A', {}); break;
            case 'w': {
                std::size_t at = 4;
                std::uint32_t flags = 0;
                std::memcpy(&flags, payload.data(), 4);
                flags = ntohl(flags);
                if (flags & 0x02) at += 8;   // region
                if (!(flags & 0x04)) break;  // no text
                std::uint32_t size = 0;
                std::memcpy(&size, payload.data() + at, 4);
                std::string text(reinterpret_cast<const char*>(payload.data() + at + 4), ntohl(size));
                while (!text.empty() && text.back() == ' ') text.pop_back();
                std::function<void(const std::string&)> f2;
                {
                    std::lock_guard<std::mutex> l(mutex_);
                    writes_.push_back(text);
                    f2 = onWrite_;
                }
                if (f2) f2(text);
                break;
            }
            default: break;   // anything else needs no answer here
            }
        }
    }

    int listen_ = -1, client_ = -1;
    int port_ = 0;
    std::thread thread_;
    std::atomic<bool> stop_ {false}, enteredTty_ {false};
    mutable std::mutex mutex_;
    std::vector<std::string> writes_;
    std::vector<std::uint32_t> pendingKeys_;
    std::function<void(const std::string&)> onWrite_;
};

} // namespace armadillo::test

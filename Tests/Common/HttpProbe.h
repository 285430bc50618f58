#pragma once
// Talking to the web page's server as a browser would, over a real loopback socket, with requests
// written byte for byte (so a test can send what no browser would: a foreign Host, a foreign
// Origin, a path outside the page):
//     std::string reply;
//     CHECK(armadillo::testing::httpSend(port, armadillo::testing::httpGet(port, "/api/status"), &reply) == 200);
#include <arpa/inet.h>
#include <cstdint>
#include <netinet/in.h>
#include <string>
#include <sys/socket.h>
#include <unistd.h>

namespace armadillo::testing {

/// Sends `request` raw to 127.0.0.1:port and reads until the server closes; returns the status
/// code (0 when nothing came back within 5 s). `reply` gets the whole response.
inline int httpSend(int port, const std::string& request, std::string* reply = nullptr)
{
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a {};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    timeval tv {5, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        ::close(fd);
        return 0;
    }
    (void) ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
    std::string got;
    char buf[4096];
    for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0;) got.append(buf, static_cast<std::size_t>(n));
    ::close(fd);
    if (reply) *reply = got;
    return got.rfind("HTTP/1.1 ", 0) == 0 ? std::stoi(got.substr(9, 3)) : 0;
}

/// A GET of `path` with this machine's Host.
inline std::string httpGet(int port, const std::string& path)
{
    return "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\nConnection: close\r\n\r\n";
}

/// A state change as the page sends it: its Origin and the session's token in a header.
inline std::string httpPost(int port, const std::string& path, const std::string& body, const std::string& origin, const std::string& token)
{
    return "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\nOrigin: " + origin +
           "\r\nX-Armadillo-Token: " + token + "\r\nContent-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
}

/// The session's token, as the page finds it in its own HTML ("" when the page has none).
inline std::string pageToken(int port)
{
    std::string page;
    httpSend(port, httpGet(port, "/"), &page);
    const std::size_t at = page.find("armadillo-token\" content=\"");
    return at == std::string::npos ? std::string() : page.substr(at + 26, 32);
}

} // namespace armadillo::testing

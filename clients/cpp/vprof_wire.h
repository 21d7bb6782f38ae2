// Length-delimited vprof.v1.Request / Response over a TCP socket, with protobuf's own
// delimited-message helpers (SerializeDelimitedToZeroCopyStream /
// ParseDelimitedFromZeroCopyStream).
#pragma once
#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <google/protobuf/io/zero_copy_stream_impl.h>
#include <google/protobuf/util/delimited_message_util.h>

#include "vprof/v1/vprof.pb.h"

namespace vprofwire {

class Connection {
 public:
  Connection(const std::string& host, int port) {
    addrinfo hints{}, *res = nullptr;
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &res) != 0 || !res)
      throw std::runtime_error("cannot resolve " + host);
    fd_ = socket(res->ai_family, res->ai_socktype, res->ai_protocol);
    if (fd_ < 0 || connect(fd_, res->ai_addr, res->ai_addrlen) != 0) {
      freeaddrinfo(res);
      throw std::runtime_error("cannot connect to " + host + ":" + std::to_string(port));
    }
    freeaddrinfo(res);
    int one = 1;
    setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    in_ = std::make_unique<google::protobuf::io::FileInputStream>(fd_);
  }
  ~Connection() {
    in_.reset();
    if (fd_ >= 0) close(fd_);
  }
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  void send(const vprof::v1::Request& req) {
    google::protobuf::io::FileOutputStream out(fd_);
    if (!google::protobuf::util::SerializeDelimitedToZeroCopyStream(req, &out) || !out.Flush())
      throw std::runtime_error("send failed");
  }
  // False at a clean end of stream.
  bool receive(vprof::v1::Response* resp) {
    bool clean_eof = false;
    if (!google::protobuf::util::ParseDelimitedFromZeroCopyStream(resp, in_.get(), &clean_eof)) {
      if (clean_eof) return false;
      throw std::runtime_error("bad or truncated response frame");
    }
    return true;
  }
  vprof::v1::Response call(const vprof::v1::Request& req) {
    send(req);
    vprof::v1::Response resp;
    if (!receive(&resp)) throw std::runtime_error("daemon closed the connection");
    return resp;
  }

 private:
  int fd_ = -1;
  std::unique_ptr<google::protobuf::io::FileInputStream> in_;
};

// Serialized messages to a file, each preceded by its length as a varint: the daemon's framing.
inline void write_frames(const std::string& path, const std::vector<std::string>& frames) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + path);
  for (const std::string& b : frames) {
    std::string prefix;
    size_t n = b.size();
    do {
      unsigned char byte = n & 0x7f;
      n >>= 7;
      if (n) byte |= 0x80;
      prefix.push_back((char)byte);
    } while (n);
    f << prefix << b;
  }
}

inline std::string read_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot read " + path);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace vprofwire

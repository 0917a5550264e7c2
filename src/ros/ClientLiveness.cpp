#include "pkm_accuracy/ros/ClientLiveness.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>

#include <ros/master.h>
#include <ros/network.h>
#include <ros/this_node.h>
#include <xmlrpcpp/XmlRpcValue.h>

namespace pkm_accuracy {
namespace ros_layer {

std::string goalClient(const std::string& goal_id) {
  const std::size_t dash = goal_id.find('-');
  if (dash == std::string::npos || dash < 2 || goal_id.front() != '/') return "";
  return goal_id.substr(0, dash);
}

std::string lookupNodeUri(const std::string& node) {
  if (node.empty() || node.front() != '/') return "";
  XmlRpc::XmlRpcValue request, response, payload;
  request[0] = ros::this_node::getName();
  request[1] = node;
  if (!ros::master::execute("lookupNode", request, response, payload, /*wait_for_master=*/false)) return "";
  if (payload.getType() != XmlRpc::XmlRpcValue::TypeString) return "";
  return static_cast<std::string>(payload);
}

Liveness probeUri(const std::string& uri, double timeout_s) {
  std::string host;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(uri, host, port) || port == 0) return Liveness::Unknown;
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0 || !found) {
    return Liveness::Unknown;
  }
  Liveness answer = Liveness::Unknown;
  bool refused_everywhere = true;
  for (addrinfo* a = found; a && answer != Liveness::Alive; a = a->ai_next) {
    const int fd = socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      refused_everywhere = false;
      continue;
    }
    int rc = connect(fd, a->ai_addr, a->ai_addrlen);
    int err = rc == 0 ? 0 : errno;
    if (rc != 0 && err == EINPROGRESS) {
      pollfd p{fd, POLLOUT, 0};
      rc = poll(&p, 1, static_cast<int>(timeout_s * 1000.0));
      if (rc == 1) {
        socklen_t len = sizeof(err);
        if (getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
      } else {
        err = ETIMEDOUT;
      }
    }
    close(fd);
    if (err == 0) {
      answer = Liveness::Alive;
    } else if (err != ECONNREFUSED) {
      refused_everywhere = false;
    }
  }
  freeaddrinfo(found);
  if (answer == Liveness::Alive) return answer;
  return refused_everywhere ? Liveness::Gone : Liveness::Unknown;
}

}  // namespace ros_layer
}  // namespace pkm_accuracy

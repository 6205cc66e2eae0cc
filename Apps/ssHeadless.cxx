#include "ssHeadless.h"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace ssapp
{
PrivateDisplay::~PrivateDisplay()
{
  this->Stop();
}

void PrivateDisplay::Stop()
{
  if (this->Pid > 0)
  {
    kill(this->Pid, SIGTERM);
    int status = 0;
    waitpid(this->Pid, &status, 0);
    this->Pid = -1;
  }
}

bool PrivateDisplay::EnsureDisplay(std::string& message)
{
  const char* display = std::getenv("DISPLAY");
  if (display && *display)
  {
    return true;
  }
  int fds[2];
  if (pipe(fds) != 0)
  {
    message = std::string("cannot create a pipe for Xvfb: ") + std::strerror(errno);
    return false;
  }
  const pid_t pid = fork();
  if (pid < 0)
  {
    message = std::string("cannot fork Xvfb: ") + std::strerror(errno);
    return false;
  }
  if (pid == 0)
  {
    // child: Xvfb writes the display number it picked to fds[1] (-displayfd),
    // so concurrent programs never race for a display number.
    close(fds[0]);
    const int devnull = open("/dev/null", O_RDWR);
    if (devnull >= 0)
    {
      dup2(devnull, 1);
      dup2(devnull, 2);
    }
    const std::string fd = std::to_string(fds[1]);
    execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "4096x4096x24", "-nolisten",
      "tcp", static_cast<char*>(nullptr));
    _exit(127);
  }
  close(fds[1]);
  this->Pid = pid;
  std::string number;
  pollfd p{ fds[0], POLLIN, 0 };
  // Xvfb starts in well under a second; give it 15 s on a loaded machine.
  while (poll(&p, 1, 15000) > 0)
  {
    char ch;
    const ssize_t n = read(fds[0], &ch, 1);
    if (n <= 0 || ch == '\n')
    {
      break;
    }
    number += ch;
  }
  close(fds[0]);
  if (number.empty())
  {
    this->Stop();
    message = "DISPLAY is not set and a private Xvfb could not be started (is the 'xvfb' "
              "package installed?)";
    return false;
  }
  setenv("DISPLAY", (":" + number).c_str(), 1);
  return true;
}
}

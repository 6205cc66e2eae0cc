#include "ssHeadless.h"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <random>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

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
    // DISPLAY was unset before the server started (else none is started);
    // do not leave it naming a server that is gone.
    unsetenv("DISPLAY");
  }
}

bool PrivateDisplay::EnsureDisplay(std::string& message)
{
  const char* display = std::getenv("DISPLAY");
  if (display && *display)
  {
    return true;
  }
  // A random display number in a high range, not the lowest free one: when
  // another program's Xvfb exits just as ours starts on the number it freed,
  // the exiting server can unlink our socket.
  std::random_device rd;
  std::mt19937 rng(rd() ^ static_cast<unsigned>(getpid()));
  std::uniform_int_distribution<int> pick(200, 30199);
  for (int attempt = 0; attempt < 20; ++attempt)
  {
    const int num = pick(rng);
    const std::string lock = "/tmp/.X" + std::to_string(num) + "-lock";
    const std::string socket = "/tmp/.X11-unix/X" + std::to_string(num);
    if (access(lock.c_str(), F_OK) == 0)
    {
      continue;
    }
    // Everything the child needs is prepared before fork: after fork only
    // async-signal-safe calls are allowed (VTK may already run threads).
    const std::string d = ":" + std::to_string(num);
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid < 0)
    {
      message = std::string("cannot fork Xvfb: ") + std::strerror(errno);
      return false;
    }
    if (pid == 0)
    {
      const int devnull = open("/dev/null", O_RDWR);
      if (devnull >= 0)
      {
        dup2(devnull, 1);
        dup2(devnull, 2);
      }
#ifdef __linux__
      // If this program dies without running its destructors (a signal),
      // the server goes with it instead of lingering.
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (getppid() != parent)
      {
        _exit(127);
      }
#else
      (void)parent;
#endif
      // -noreset: an X server resets (and refuses connections) whenever its
      // last client disconnects, which a window closed and reopened can hit.
      execlp("Xvfb", "Xvfb", d.c_str(), "-screen", "0", "4096x4096x24", "-nolisten", "tcp",
        "-noreset", static_cast<char*>(nullptr));
      _exit(127);
    }
    this->Pid = pid;
    // Xvfb starts in well under a second; allow 15 s on a loaded machine.
    bool up = false;
    for (int i = 0; i < 300 && !up; ++i)
    {
      int status = 0;
      if (waitpid(pid, &status, WNOHANG) == pid)
      {
        this->Pid = -1; // it exited: number taken or Xvfb missing
        break;
      }
      // ready when the socket accepts a connection (the file appears
      // before the server listens)
      const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
      if (fd >= 0)
      {
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::strncpy(addr.sun_path, socket.c_str(), sizeof(addr.sun_path) - 1);
        up = ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0;
        ::close(fd);
      }
      if (!up)
      {
        usleep(50000);
      }
    }
    if (up)
    {
      setenv("DISPLAY", (":" + std::to_string(num)).c_str(), 1);
      return true;
    }
    this->Stop();
  }
  message = "DISPLAY is not set and a private Xvfb could not be started (is the 'xvfb' "
            "package installed?)";
  return false;
}
}

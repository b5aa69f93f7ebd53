// DDGBuildRanks.cxx: the design volume broadcast, the ranks' TCP links, the exemplar workers.
#include "DDGBuildRanks.h"

#include "Common/Error.h"

#include <vtkClientSocket.h>
#include <vtkNew.h>
#include <vtkServerSocket.h>
#include <vtkSmartPointer.h>
#include <vtkSocketCollection.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <unistd.h>

namespace ddg
{
namespace
{
constexpr unsigned long kConnectMs = 30000;
constexpr int kChunk = 1 << 26;

// A message: its length (8 bytes), then its bytes.
void sendMessage(vtkSocket* socket, const std::string& message)
{
  const std::uint64_t n = message.size();
  bool ok = socket->Send(&n, sizeof(n)) != 0;
  for (std::uint64_t at = 0; ok && at < n; at += kChunk)
    ok = socket->Send(
           message.data() + at, static_cast<int>(std::min<std::uint64_t>(kChunk, n - at))) != 0;
  if (!ok)
    throw Error("the build's connection to another rank broke (it stopped?)");
}

// The next message; with `stop`, waits in steps of 1 s and gives up when it is set. (VTK's select
// reads the milliseconds below a second as microseconds: whole seconds wait as long as asked.)
std::string receiveMessage(vtkSocket* socket, const std::atomic<bool>* stop)
{
  if (stop)
  {
    vtkNew<vtkSocketCollection> one;
    one->AddItem(socket);
    for (;;)
    {
      if (*stop)
        throw Cancelled();
      const int selected = one->SelectSockets(1000);
      if (selected < 0)
        throw Error("the build's connection to the first rank broke");
      if (selected > 0)
        break;
    }
  }
  std::uint64_t n = 0;
  if (!socket->Receive(&n, sizeof(n)))
    throw Error("the build's connection to another rank closed (it stopped?)");
  std::string message(n, '\0');
  for (std::uint64_t at = 0; at < n; at += kChunk)
    if (!socket->Receive(&message[at], static_cast<int>(std::min<std::uint64_t>(kChunk, n - at))))
      throw Error("the build's connection to another rank closed in a message");
  return message;
}

class RankWorkers : public ExemplarWorkers
{
public:
  explicit RankWorkers(std::vector<vtkSmartPointer<vtkClientSocket>> sockets)
    : Sockets(std::move(sockets))
  {
  }
  ~RankWorkers() override
  {
    for (auto& s : Sockets)
    {
      try
      {
        sendMessage(s, "end");
      }
      catch (...)
      {
      }
      s->CloseSocket();
    }
  }
  int size() const override { return static_cast<int>(Sockets.size()); }
  void send(int worker, const std::string& message) override
  {
    onRank(worker, [&](vtkClientSocket* s) { sendMessage(s, message); });
  }
  std::string receive(int worker) override
  {
    std::string message;
    onRank(worker, [&](vtkClientSocket* s) { message = receiveMessage(s, nullptr); });
    return message;
  }

private:
  // Runs `f` on worker's connection; its failure names the worker's rank.
  template <class F>
  void onRank(int worker, const F& f)
  {
    try
    {
      f(Sockets[static_cast<size_t>(worker)]);
    }
    catch (const Error& e)
    {
      throw Error("rank " + std::to_string(worker + 1) + ": " + e.what());
    }
  }
  std::vector<vtkSmartPointer<vtkClientSocket>> Sockets;
};

std::string hostName()
{
  char name[256] = { 0 };
  if (gethostname(name, sizeof(name) - 1) != 0 || !name[0])
    return "localhost";
  return name;
}
} // namespace

BuildCrew buildCrewOnRanks(const RankGroup& ranks, const DesignSpaceInput& input)
{
  // 1. the design-space volume on every rank (the same bits: the same exemplars)
  std::string header;
  std::vector<float> values;
  ranks.step( // the first rank's copy may fail (memory): every rank stops with it
    [&]
    {
      if (ranks.rank() != 0)
        return;
      const Volume& v = input.volume;
      header = nlohmann::json{
        { "dims", v.dims() }, { "origin", v.origin() }, { "spacing", v.spacing() },
        { "type", static_cast<int>(v.originalType()) }
      }.dump();
      values = v.floatValues();
    });
  header = ranks.broadcast(header);
  ranks.broadcast(values);
  std::shared_ptr<Volume> volume;
  ranks.step(
    [&]
    {
      if (ranks.rank() == 0)
        return;
      const auto j = nlohmann::json::parse(header);
      volume = std::make_shared<Volume>(j.at("dims").get<std::array<int, 3>>(),
        j.at("origin").get<std::array<double, 3>>(), j.at("spacing").get<std::array<double, 3>>(),
        std::move(values), static_cast<ScalarType>(j.at("type").get<int>()));
    });
  values = {};
  // 2. every other rank connects to a port of the first's
  vtkNew<vtkServerSocket> server;
  std::string address;
  if (ranks.rank() == 0 && server->CreateServer(0) == 0)
    address = hostName() + " " + std::to_string(server->GetServerPort());
  address = ranks.broadcast(address);
  vtkSmartPointer<vtkClientSocket> link;
  std::vector<vtkSmartPointer<vtkClientSocket>> links(static_cast<size_t>(ranks.size() - 1));
  ranks.step(
    [&]
    {
      if (address.empty())
        throw Error("the first rank cannot open a port for the build's exemplar renders");
      const std::string host = address.substr(0, address.rfind(' '));
      const int port = std::stoi(address.substr(address.rfind(' ') + 1));
      if (ranks.rank() != 0)
      {
        link = vtkSmartPointer<vtkClientSocket>::New();
        const int rank = ranks.rank();
        if (link->ConnectToServer(host.c_str(), port) != 0 || !link->Send(&rank, sizeof(rank)))
          throw Error("cannot connect to the first rank's build port " + address);
        return;
      }
      for (int n = 1; n < ranks.size(); ++n)
      {
        vtkSmartPointer<vtkClientSocket> s;
        s.TakeReference(server->WaitForConnection(kConnectMs));
        int rank = 0;
        if (!s || !s->Receive(&rank, sizeof(rank)) || rank < 1 || rank >= ranks.size() ||
          links[static_cast<size_t>(rank - 1)])
          throw Error("the other ranks did not connect to the build's port " + address);
        links[static_cast<size_t>(rank - 1)] = s;
      }
    });
  BuildCrew crew;
  if (ranks.rank() == 0)
    crew.workers = std::make_unique<RankWorkers>(std::move(links));
  else
    crew.serve = [volume, link](const std::atomic<bool>& stop)
    {
      serveExemplars(
        *volume, [&] { return receiveMessage(link, &stop); },
        [&](const std::string& m) { sendMessage(link, m); });
    };
  return crew;
}

} // namespace ddg

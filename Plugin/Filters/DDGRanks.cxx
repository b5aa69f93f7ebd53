// DDGRanks.cxx: collective steps over VTK's multiprocess controller.
#include "DDGRanks.h"

#include "Render/PieceExchange.h" // ddg::PieceFailed
#include "Render/RayCaster.h"     // ddg::Cancelled

#include <vtkCommunicator.h>
#include <vtkInformation.h>
#include <vtkMultiProcessController.h>
#include <vtkMultiProcessStream.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <algorithm>
#include <memory>

namespace ddg
{

RankGroup::RankGroup(vtkMultiProcessController* controller)
  : Controller(controller)
  , Rank(controller->GetLocalProcessId())
  , Size(controller->GetNumberOfProcesses())
{
}

std::unique_ptr<RankGroup> RankGroup::forRequest(vtkInformation* outInfo)
{
  std::unique_ptr<RankGroup> ranks = global();
  if (!ranks || !outInfo ||
    !outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) ||
    !outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()))
    return nullptr;
  if (outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) != ranks->size() ||
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) != ranks->rank())
    return nullptr;
  return ranks;
}

std::unique_ptr<RankGroup> RankGroup::global()
{
  vtkMultiProcessController* c = vtkMultiProcessController::GetGlobalController();
  if (!c || c->GetNumberOfProcesses() < 2)
    return nullptr;
  return std::unique_ptr<RankGroup>(new RankGroup(c));
}

void RankGroup::step(const std::function<void()>& work) const
{
  enum
  {
    Done = 0,
    Stopped = 1,  // cancelled
    Followed = 2, // stopped because another piece failed (PieceFailed): that one reports
    Failed = 3
  };
  int status = Done;
  std::string message;
  try
  {
    work();
  }
  catch (const Cancelled&)
  {
    status = Stopped;
  }
  catch (const PieceFailed&)
  {
    status = Followed;
  }
  catch (const RankFailed& e)
  {
    status = Failed;
    message = e.what();
  }
  catch (const std::exception& e)
  {
    status = Failed;
    message = e.what();
  }
  const std::vector<int> all = allGather(&status, 1);
  int failed = -1, worst = Done;
  for (int r = 0; r < Size; ++r)
  {
    worst = std::max(worst, all[static_cast<size_t>(r)]);
    if (failed < 0 && all[static_cast<size_t>(r)] == Failed)
      failed = r;
  }
  if (failed < 0 && worst == Followed) // cannot happen: some piece failed first
  {
    if (Rank == 0)
      throw Error("a volume piece failed without saying why");
    throw RankFailed("a volume piece failed");
  }
  if (worst == Done)
    return;
  if (failed < 0) // only cancellations
  {
    if (Rank == 0)
      throw Cancelled();
    throw RankFailed("cancelled");
  }
  // the failing rank's message to the first rank
  vtkMultiProcessStream stream;
  if (Rank == failed)
    stream << message;
  Controller->Broadcast(stream, failed);
  std::string text;
  stream >> text;
  if (failed != 0)
    text = "rank " + std::to_string(failed) + ": " + text;
  if (Rank == 0)
    throw Error(text);
  throw RankFailed(text);
}

void RankGroup::allMin(double* values, int count) const
{
  std::vector<double> in(values, values + count);
  Controller->AllReduce(in.data(), values, count, vtkCommunicator::MIN_OP);
}

void RankGroup::allMax(double* values, int count) const
{
  std::vector<double> in(values, values + count);
  Controller->AllReduce(in.data(), values, count, vtkCommunicator::MAX_OP);
}

void RankGroup::allSum(double* values, int count) const
{
  std::vector<double> in(values, values + count);
  Controller->AllReduce(in.data(), values, count, vtkCommunicator::SUM_OP);
}

std::vector<int> RankGroup::allGather(const int* values, int count) const
{
  std::vector<int> out(static_cast<size_t>(count) * Size);
  Controller->AllGather(values, out.data(), count);
  return out;
}

void RankGroup::allGather(const float* values, long long count, float* all) const
{
  Controller->AllGather(values, all, static_cast<vtkIdType>(count));
}

void RankGroup::broadcast(std::vector<float>& values) const
{
  vtkIdType count = static_cast<vtkIdType>(values.size());
  Controller->Broadcast(&count, 1, 0);
  values.resize(static_cast<size_t>(count));
  if (count > 0)
    Controller->Broadcast(values.data(), count, 0);
}

std::vector<float> RankGroup::gatherToFirst(
  const std::vector<float>& values, const std::vector<long long>& counts) const
{
  std::vector<vtkIdType> lengths(counts.begin(), counts.end()), offsets;
  vtkIdType total = 0;
  for (vtkIdType n : lengths)
  {
    offsets.push_back(total);
    total += n;
  }
  std::vector<float> out(Rank == 0 ? static_cast<size_t>(total) : 0);
  // (GatherV reads the send buffer even when empty: give it a valid pointer)
  const float none = 0;
  Controller->GatherV(values.empty() ? &none : values.data(), Rank == 0 ? out.data() : nullptr,
    static_cast<vtkIdType>(values.size()), lengths.data(), offsets.data(), 0);
  return out;
}

std::string RankGroup::broadcast(const std::string& text) const
{
  vtkMultiProcessStream stream;
  if (Rank == 0)
    stream << text;
  Controller->Broadcast(stream, 0);
  std::string out;
  stream >> out;
  return out;
}

} // namespace ddg

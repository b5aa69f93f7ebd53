// vtkDDGBuildDesignSpace.cxx: converts the input and calls ddg::buildDesignSpace.
#include "vtkDDGBuildDesignSpace.h"

#include "DDGBuildRanks.h"
#include "DDGFilterSupport.h"
#include "DDGPieces.h"
#include "DDGRanks.h"
#include "DDGVolumeAdaptor.h"

#include "Gallery/BuildDesignSpace.h"

#include "Render/RayCaster.h" // ddg::Cancelled

#include <vtkAlgorithmOutput.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

vtkStandardNewMacro(vtkDDGBuildDesignSpace);

// The background build: its thread and what it reports (guarded by Mutex; the getters copy it
// into the *Shown members, read on the calling thread only).
struct vtkDDGBuildDesignSpace::Background
{
  std::thread Thread; // the build (under MPI: the first rank's), or a rank's exemplar server
  std::atomic<bool> Cancel{ false };
  std::atomic<bool> StopServing{ false }; // the other ranks' server: set when the filter goes
  std::mutex Mutex;
  std::string State = "idle", Stage, Error;
  double Fraction = 0;
  std::chrono::steady_clock::time_point Start, End;
  bool Ended = false;
  double Figures[6] = { 0, 0, 0, 0, 0, 0 };
  // copies handed out by the getters
  std::string StateShown, StageShown, ErrorShown, Plan;
  // the rates PlanBuild measured, for the build that follows on the same input and size (it
  // then follows the plan shown)
  ddg::BuildRates PlanRates;
  std::uint64_t PlanInputVersion = 0, InputVersion = 0; // ddg::volumeVersion
  int PlanSize = 0;
  double FiguresShown[6] = { 0, 0, 0, 0, 0, 0 };
  // under MPI, the first rank's design-space input of the pieces last streamed (InputOnRanks:
  // PlanBuild then StartBuild stream once), and what it was made of (with InputVersion)
  ddg::DesignSpaceInput RanksInput;
  vtkIdType RanksVoxels = 0;
  std::string RanksArray;

  void join()
  {
    this->Cancel = true;
    this->StopServing = true;
    if (this->Thread.joinable())
      this->Thread.join();
  }
  double elapsed() const
  {
    const auto end = this->Ended ? this->End : std::chrono::steady_clock::now();
    return this->State == "idle" ? 0 : std::chrono::duration<double>(end - this->Start).count();
  }
  void finish(const std::string& state, const std::string& error = "")
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->State = state;
    this->Error = error;
    this->End = std::chrono::steady_clock::now();
    this->Ended = true;
  }
};

vtkDDGBuildDesignSpace::vtkDDGBuildDesignSpace()
  : Worker(new Background)
{
}

vtkDDGBuildDesignSpace::~vtkDDGBuildDesignSpace()
{
  this->Worker->join(); // cancels a running build (it stops within ~0.5 s, nothing left)
}

void vtkDDGBuildDesignSpace::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "OutputDirectory: " << this->OutputDirectory << "\n";
  os << indent << "SpecFile: " << this->SpecFile << "\n";
  os << indent << "Count: " << this->Count << "\n";
  os << indent << "Size: " << this->Size << "\n";
  os << indent << "Minutes: " << this->Minutes << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "OutlineCount: " << this->OutlineCount << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "BudgetMinutes: " << this->BudgetMinutes << "\n";
  os << indent << "Overwrite: " << this->Overwrite << "\n";
  os << indent << "DesignVoxels: " << this->DesignVoxels << "\n";
}

ddg::BuildOptions vtkDDGBuildDesignSpace::Options() const
{
  ddg::BuildOptions o;
  if (!this->SpecFile.empty())
    o.spec = ddg::readDesignSpaceSpec(this->SpecFile);
  o.count = this->Count;
  o.size = this->Size;
  o.minutes = this->Minutes;
  o.iterations = this->Iterations;
  o.outlineCount = this->OutlineCount;
  o.seed = static_cast<std::uint64_t>(this->Seed);
  o.budgetMinutes = this->BudgetMinutes;
  o.overwrite = this->Overwrite;
  o.maxDesignVoxels = static_cast<std::int64_t>(this->DesignVoxels);
  return o;
}

ddg::Volume vtkDDGBuildDesignSpace::InputVolume()
{
  if (this->GetNumberOfInputConnections(0) < 1)
    throw ddg::Error("no input volume");
  vtkAlgorithmOutput* connection = this->GetInputConnection(0, 0);
  vtkAlgorithm* producer = connection->GetProducer();
  const int port = connection->GetIndex();
  if (port == 0)
    producer->UpdatePiece(0, 1, 0);
  else
    producer->Update(port);
  vtkImageData* image = vtkImageData::SafeDownCast(producer->GetOutputDataObject(port));
  if (!image)
    throw ddg::Error("the input is not a volume (image data)");
  vtkDataArray* array = this->GetInputArrayToProcess(0, image);
  this->Worker->InputVersion = ddg::volumeVersion(image, array);
  return ddg::toCoreVolume(image, array);
}

ddg::DesignSpaceInput vtkDDGBuildDesignSpace::InputOnRanks(const ddg::RankGroup& ranks)
{
  using SDDP = vtkStreamingDemandDrivenPipeline;
  vtkImageData* image = nullptr;
  vtkDataArray* array = nullptr;
  int whole[6] = { 0, -1, 0, -1, 0, -1 };
  ranks.step(
    [&]
    {
      if (this->GetNumberOfInputConnections(0) < 1)
        throw ddg::Error("no input volume");
      vtkAlgorithmOutput* connection = this->GetInputConnection(0, 0);
      vtkAlgorithm* producer = connection->GetProducer();
      const int port = connection->GetIndex();
      vtkNew<vtkInformationVector> requests; // one per output port: this rank's piece on ours
      requests->SetNumberOfInformationObjects(port + 1);
      vtkInformation* request = requests->GetInformationObject(port);
      request->Set(SDDP::UPDATE_PIECE_NUMBER(), ranks.rank());
      request->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), ranks.size());
      request->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
      producer->Update(port, requests);
      image = vtkImageData::SafeDownCast(producer->GetOutputDataObject(port));
      if (!image)
        throw ddg::Error("the input is not a volume (image data)");
      producer->GetOutputInformation(port)->Get(SDDP::WHOLE_EXTENT(), whole);
      array = this->GetInputArrayToProcess(0, image);
    });
  Background& w = *this->Worker;
  const std::string arrayName = array && array->GetName() ? array->GetName() : "";
  const std::uint64_t version = ddg::volumeVersion(image, array);
  double changed =
    version != w.InputVersion || arrayName != w.RanksArray || this->DesignVoxels != w.RanksVoxels;
  ranks.allMax(&changed, 1); // every rank streams again when one piece changed
  if (changed > 0)
  {
    w.RanksInput = ddg::DesignSpaceInput();
    w.InputVersion = 0; // nothing kept until the streaming succeeds
    const ddg::RankVolume pieces = ddg::RankVolume::gather(ranks, image, array, whole, false);
    w.RanksInput = ddg::designSpaceInputOnRanks(ranks, pieces, this->DesignVoxels);
    w.InputVersion = version;
    w.RanksArray = arrayName;
    w.RanksVoxels = this->DesignVoxels;
  }
  return w.RanksInput;
}

ddg::BuildOptions vtkDDGBuildDesignSpace::CheckedOptions(const ddg::RankGroup* ranks)
{
  ddg::BuildOptions options;
  auto work = [&]()
  {
    if (this->OutputDirectory.empty())
      throw ddg::Error("no OutputDirectory set");
    if (ranks && ranks->rank() != 0)
      return;
    options = this->Options();
    // what can be refused at once is (the free disk space is checked by the build, which
    // estimates it first)
    ddg::checkBuildOutput(this->OutputDirectory, 0, options.overwrite);
  };
  if (ranks)
    ranks->step(work);
  else
    work();
  return options;
}

// --- the build in the background -----------------------------------------------------------------

void vtkDDGBuildDesignSpace::StartBuild()
{
  Background& w = *this->Worker;
  // under MPI every rank runs this command: they agree on whether the first rank is building
  const std::unique_ptr<ddg::RankGroup> ranks = ddg::RankGroup::global();
  double running = 0;
  {
    std::lock_guard<std::mutex> lock(w.Mutex);
    running = w.State == "running";
  }
  if (ranks)
    ranks->allMax(&running, 1);
  if (running > 0)
    return;
  if (w.Thread.joinable()) // a finished build; on the other ranks, the server its end ended
    w.Thread.join();
  w.Cancel = false;
  w.StopServing = false;
  {
    std::lock_guard<std::mutex> lock(w.Mutex);
    w.State = "running";
    w.Stage.clear();
    w.Error.clear();
    w.Fraction = 0;
    w.Start = std::chrono::steady_clock::now();
    w.Ended = false;
    std::fill(std::begin(w.Figures), std::end(w.Figures), 0.0);
  }
  // the volume is copied here, on the calling thread: the thread never touches the pipeline.
  // Under MPI every rank streams its piece to the first, which builds on its thread while the
  // other ranks render shares of the exemplars on theirs (over their own connections: ParaView's
  // MPI is not for threads)
  ddg::Volume volume;
  ddg::DesignSpaceInput input;
  ddg::BuildOptions options;
  std::unique_ptr<ddg::ExemplarWorkers> workers;
  try
  {
    options = this->CheckedOptions(ranks.get());
    if (ranks)
    {
      input = this->InputOnRanks(*ranks);
      ddg::BuildCrew crew = ddg::buildCrewOnRanks(*ranks, input);
      if (ranks->rank() != 0)
      {
        w.Thread = std::thread(
          [&w, serve = std::move(crew.serve)]()
          {
            try
            {
              serve(w.StopServing);
            }
            catch (const std::exception&) // the first rank's build reports
            {
            }
          });
        w.finish("done"); // the first rank builds and reports
        return;
      }
      workers = std::move(crew.workers);
      options.workers = workers.get();
    }
    else
    {
      volume = this->InputVolume();
      ddg::checkBuildVolume(volume);
    }
    if (w.PlanRates.measured() && w.PlanInputVersion == w.InputVersion && w.PlanSize == this->Size)
      options.rates = w.PlanRates;
  }
  catch (const std::exception& e)
  {
    w.finish("failed", e.what());
    return;
  }
  try
  {
    w.Thread = std::thread(
      [&w, volume = std::move(volume), input = std::move(input), options,
        workers = std::move(workers), dir = this->OutputDirectory]() mutable
      {
        std::string state = "done", error;
        try
        {
          auto progress = [&w](const std::string& stage, double f)
          {
            std::lock_guard<std::mutex> lock(w.Mutex);
            if (stage != "done")
              w.Stage = stage;
            w.Fraction = f;
            return !w.Cancel;
          };
          const auto r = input.volume.empty()
            ? ddg::buildDesignSpace(volume, "", dir, options, progress)
            : ddg::buildDesignSpace(input, "", dir, options, progress);
          std::lock_guard<std::mutex> lock(w.Mutex);
          const double figures[6] = { r.evaluation.psnr, r.evaluation.ssim, r.evaluation.emd,
            r.evaluation.invariance, r.training.seconds,
            static_cast<double>(r.training.iterations) };
          std::copy(std::begin(figures), std::end(figures), w.Figures);
        }
        catch (const ddg::Cancelled&)
        {
          state = "cancelled";
        }
        catch (const std::exception& e)
        {
          // a rank's connection that broke while cancelling is the cancel's
          state = w.Cancel ? "cancelled" : "failed";
          error = w.Cancel ? "" : e.what();
        }
        workers.reset(); // the other ranks' servers end
        w.finish(state, error);
      });
  }
  catch (const std::exception& e) // no thread (the system's limit): nothing started
  {
    w.finish("failed", e.what());
  }
}

void vtkDDGBuildDesignSpace::CancelBuild()
{
  this->Worker->Cancel = true;
}

const char* vtkDDGBuildDesignSpace::GetBuildState()
{
  std::lock_guard<std::mutex> lock(this->Worker->Mutex);
  this->Worker->StateShown = this->Worker->State;
  return this->Worker->StateShown.c_str();
}

const char* vtkDDGBuildDesignSpace::GetBuildStage()
{
  std::lock_guard<std::mutex> lock(this->Worker->Mutex);
  this->Worker->StageShown = this->Worker->Stage;
  return this->Worker->StageShown.c_str();
}

double vtkDDGBuildDesignSpace::GetBuildProgress()
{
  std::lock_guard<std::mutex> lock(this->Worker->Mutex);
  return this->Worker->Fraction;
}

double vtkDDGBuildDesignSpace::GetBuildSecondsElapsed()
{
  std::lock_guard<std::mutex> lock(this->Worker->Mutex);
  return this->Worker->elapsed();
}

double vtkDDGBuildDesignSpace::GetBuildSecondsLeft()
{
  std::lock_guard<std::mutex> lock(this->Worker->Mutex);
  const Background& w = *this->Worker;
  if (w.State != "running")
    return w.State == "idle" ? -1 : 0;
  // the stages are weighted by their estimated time: the fraction grows about linearly with it
  const double elapsed = w.elapsed();
  return w.Fraction > 0.01 && elapsed > 2 ? elapsed * (1 - w.Fraction) / w.Fraction : -1;
}

const char* vtkDDGBuildDesignSpace::GetBuildError()
{
  std::lock_guard<std::mutex> lock(this->Worker->Mutex);
  this->Worker->ErrorShown = this->Worker->Error;
  return this->Worker->ErrorShown.c_str();
}

double* vtkDDGBuildDesignSpace::GetBuildFigures()
{
  std::lock_guard<std::mutex> lock(this->Worker->Mutex);
  std::copy(
    std::begin(this->Worker->Figures), std::end(this->Worker->Figures), this->Worker->FiguresShown);
  return this->Worker->FiguresShown;
}

void vtkDDGBuildDesignSpace::PlanBuild()
{
  nlohmann::json j;
  const std::unique_ptr<ddg::RankGroup> ranks = ddg::RankGroup::global();
  try
  {
    if (!(this->BudgetMinutes > 0))
      throw ddg::Error("no budget set (BudgetMinutes)");
    ddg::DesignSpaceInput input;
    ddg::Volume volume;
    if (ranks)
    {
      input = this->InputOnRanks(*ranks);
      if (ranks->rank() != 0)
        return; // the first rank plans
    }
    else
    {
      volume = this->InputVolume();
      ddg::checkBuildVolume(volume);
    }
    Background& w = *this->Worker;
    const bool again =
      w.PlanRates.measured() && w.PlanInputVersion == w.InputVersion && w.PlanSize == this->Size;
    const ddg::BuildRates rates = again ? w.PlanRates : ddg::BuildRates();
    const ddg::BuildPlan plan = ranks
      ? ddg::planBuild(input, this->BudgetMinutes, this->Size, 0, rates)
      : ddg::planBuild(volume, this->BudgetMinutes, this->Size, 0, rates,
          static_cast<std::int64_t>(this->DesignVoxels));
    w.PlanRates = plan.rates;
    w.PlanInputVersion = w.InputVersion;
    w.PlanSize = this->Size;
    j = nlohmann::json::parse(plan.toJson());
    j["describe"] = plan.describe();
    if (!this->OutputDirectory.empty())
    {
      try
      {
        ddg::checkBuildOutput(this->OutputDirectory, plan.diskBytes, this->Overwrite);
      }
      catch (const std::exception& e)
      {
        j["output_error"] = e.what();
      }
    }
  }
  catch (const std::exception& e)
  {
    j = nlohmann::json{ { "error", e.what() } };
  }
  this->Worker->Plan = j.dump();
}

const char* vtkDDGBuildDesignSpace::GetBuildPlan()
{
  return this->Worker->Plan.c_str();
}

int vtkDDGBuildDesignSpace::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
  return 1;
}

void vtkDDGBuildDesignSpace::Execute(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  vtkTable* output = vtkTable::GetData(outputVector);
  const ddg::RankGroup* ranks = this->Ranks();
  const ddg::BuildOptions o = this->CheckedOptions(ranks);
  auto progress = [this](const std::string&, double f)
  {
    this->UpdateProgress(f);
    return !this->GetAbortExecute();
  };
  ddg::BuildReport r;
  if (ranks) // every rank its piece: the points stream to the first rank, which builds alone
  {
    const ddg::RankVolume pieces =
      ddg::RankVolume::gather(*ranks, input, array, this->InputWholeExtent(), false);
    const ddg::DesignSpaceInput in =
      ddg::designSpaceInputOnRanks(*ranks, pieces, this->DesignVoxels);
    // the other ranks render shares of the exemplars until the first rank's build ends
    ddg::BuildCrew crew = ddg::buildCrewOnRanks(*ranks, in);
    if (ranks->rank() != 0)
    {
      const std::atomic<bool> never{ false };
      crew.serve(never);
      return;
    }
    ddg::BuildOptions withRanks = o;
    withRanks.workers = crew.workers.get();
    r = ddg::buildDesignSpace(in, "", this->OutputDirectory, withRanks, progress);
  }
  else
    r = ddg::buildDesignSpace(
      ddg::toCoreVolume(input, array), "", this->OutputDirectory, o, progress);
  auto add = [output](const char* name, double v)
  {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->InsertNextValue(v);
    output->AddColumn(a);
  };
  add("PSNR", r.evaluation.psnr);
  add("SSIM", r.evaluation.ssim);
  add("EMD", r.evaluation.emd);
  add("Invariance", r.evaluation.invariance);
  add("TrainingSeconds", r.training.seconds);
  add("Iterations", r.training.iterations);
  auto dir = vtkSmartPointer<vtkStringArray>::New();
  dir->SetName("ModelDirectory");
  dir->InsertNextValue(this->OutputDirectory);
  output->GetFieldData()->AddArray(dir);
  // under MPI: the exemplar candidates the other ranks rendered
  auto elsewhere = vtkSmartPointer<vtkDoubleArray>::New();
  elsewhere->SetName("OtherRanksCandidates");
  elsewhere->InsertNextValue(r.workerCandidates);
  output->GetFieldData()->AddArray(elsewhere);
}

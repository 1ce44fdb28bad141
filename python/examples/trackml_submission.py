"""A real TrackML event (data/trackml, Kaggle train_100_events) through the
conformal tracking: read, reconstruct, write a TrackML submission.

    PYTHONPATH=build/python python3 python/examples/trackml_submission.py
"""
import pathlib

import conftrack

folder = (pathlib.Path(__file__).resolve().parents[2] / "data" / "trackml" /
          "train_100_events_no_truth")
event = conftrack.read_event(folder, 1001)
print(f"event {event.number}: {len(event.hits)} hits, "
      f"{len(event.particles)} particles")

result = conftrack.reconstruct(event.hits, detector="trackml")
tracks = result.tracks
print(f"{len(tracks)} tracks; {(result.hit_tracks.track_id > 0).mean():.1%} "
      f"of the hits on tracks; median pT {tracks.pt.median():.2f} GeV")
print(result.statistics)

result.submission(event.number).to_csv("event000001001-submission.csv",
                                       index=False)
print("wrote event000001001-submission.csv")

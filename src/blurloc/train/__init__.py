"""Training: shared loop utilities (:mod:`.loop`), the trainers' settings (:mod:`.config`), the
torch Datasets (:mod:`.datasets`), the video-deblurring trainer (:mod:`.video`) and the pose
trainer (:mod:`.pose`)."""

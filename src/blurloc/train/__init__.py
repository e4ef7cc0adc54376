"""Training: shared loop utilities (:mod:`.loop`), the torch Datasets (:mod:`.datasets`), the
video-deblurring trainer (:mod:`.video`) and the pose trainer (:mod:`.pose`)."""

"""Neural networks: recurrent video deblurring (eq. 8-11) and camera pose regression."""
